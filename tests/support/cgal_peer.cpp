// CGAL as a peer and the exact oracle of the sums, in this one translation unit (CGAL is slow to
// compile): convex_hull_3 on the pairwise sums (the paper's comparator), the exact Minkowski sum
// of Nef polyhedra (minkowski_sum_3), and the exact facet structure of a sum.
#include "support/cgal_peer.hpp"

// The oracle and the peers run on one thread each: without this, every lazy exact number of
// Epeck pays a std::call_once (half the oracle's time on the rounded-tie suites). This is the
// only translation unit that includes CGAL.
#define CGAL_HAS_NO_THREADS 1

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Gmpzf.h>
#include <CGAL/Homogeneous.h>
#include <CGAL/Polytope_distance_d.h>
#include <CGAL/Polytope_distance_d_traits_3.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Polyhedron_items_with_id_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/minkowski_sum_3.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace minksum::peers {

namespace {
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Epeck = CGAL::Exact_predicates_exact_constructions_kernel;
}  // namespace

int cgal_quickhull(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                   std::vector<Eigen::Vector3d>* vertices) {
  std::vector<Epick::Point_3> sums;
  sums.reserve(a.size() * b.size());
  for (const auto& p : a)
    for (const auto& q : b) sums.emplace_back(p.x() + q.x(), p.y() + q.y(), p.z() + q.z());
  CGAL::Surface_mesh<Epick::Point_3> hull;
  CGAL::convex_hull_3(sums.begin(), sums.end(), hull);
  if (vertices) {
    vertices->clear();
    for (const auto v : hull.vertices()) {
      const auto& p = hull.point(v);
      vertices->emplace_back(p.x(), p.y(), p.z());
    }
  }
  return int(hull.number_of_faces());
}

struct CgalNefOperands::Impl {
  CGAL::Nef_polyhedron_3<Epeck> a, b;
};

CgalNefOperands::CgalNefOperands(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  const auto nef = [](const std::vector<Eigen::Vector3d>& pts) {
    std::vector<Epeck::Point_3> p;
    for (const auto& v : pts) p.emplace_back(v.x(), v.y(), v.z());
    CGAL::Polyhedron_3<Epeck> hull;
    CGAL::convex_hull_3(p.begin(), p.end(), hull);
    return CGAL::Nef_polyhedron_3<Epeck>(hull);
  };
  impl_.reset(new Impl{nef(a), nef(b)});
}

CgalNefOperands::~CgalNefOperands() = default;

int CgalNefOperands::sum() const {
  // (minkowski_sum_3 takes its operands by value: handle copies, the polyhedra are shared.)
  const CGAL::Nef_polyhedron_3<Epeck> sum = CGAL::minkowski_sum_3(impl_->a, impl_->b);
  return int(sum.number_of_vertices());
}

namespace {

// The structure of the hull of `points` (exact predicates of kernel K on its coordinates):
// triangles merged where exactly coplanar (union-find over facets); a true vertex touches at
// least three merged facets. With `facets`, each merged facet's true vertices, sorted.
// (Facets, halfedges and vertices carry their index (Polyhedron_items_with_id_3): maps and sets
// keyed by handles were a fifth of the integer-grid suites' time.)
template <class K>
ExactCounts hull_structure(const std::vector<typename K::Point_3>& points,
                           std::vector<std::vector<Eigen::Vector3d>>* facets) {
  CGAL::Polyhedron_3<K, CGAL::Polyhedron_items_with_id_3> hull;
  CGAL::convex_hull_3(points.begin(), points.end(), hull);
  CGAL::set_halfedgeds_items_id(hull);
  std::vector<int> parent(hull.size_of_facets());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[size_t(x)] != x) x = parent[size_t(x)] = parent[size_t(parent[size_t(x)])];
    return x;
  };
  const auto facet = [](const auto& h) { return int(h->facet()->id()); };
  for (auto h = hull.halfedges_begin(); h != hull.halfedges_end(); ++h) {
    const auto& a = h->vertex()->point();
    const auto& b = h->opposite()->vertex()->point();
    const auto& c = h->next()->vertex()->point();
    const auto& d = h->opposite()->next()->vertex()->point();
    if (CGAL::coplanar(a, b, c, d)) parent[size_t(find(facet(h)))] = find(facet(h->opposite()));
  }
  std::vector<char> is_class(parent.size(), 0);
  std::vector<std::pair<int, int>> adjacent;
  for (auto h = hull.halfedges_begin(); h != hull.halfedges_end(); ++h) {
    const int x = find(facet(h)), y = find(facet(h->opposite()));
    is_class[size_t(x)] = 1;
    if (x < y) adjacent.push_back({x, y});
  }
  std::sort(adjacent.begin(), adjacent.end());
  adjacent.erase(std::unique(adjacent.begin(), adjacent.end()), adjacent.end());
  std::vector<std::vector<Eigen::Vector3d>> corners(parent.size());
  std::vector<int> around;
  int V = 0;
  for (auto v = hull.vertices_begin(); v != hull.vertices_end(); ++v) {
    around.clear();
    auto h = v->vertex_begin();
    do around.push_back(find(facet(h)));
    while (++h != v->vertex_begin());
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    if (around.size() < 3) continue;
    ++V;
    const Eigen::Vector3d p(CGAL::to_double(v->point().x()), CGAL::to_double(v->point().y()),
                            CGAL::to_double(v->point().z()));
    if (facets)
      for (int c : around) corners[size_t(c)].push_back(p);
  }
  if (facets) {
    facets->clear();
    for (auto& pts : corners) {
      if (pts.empty()) continue;
      std::sort(pts.begin(), pts.end(), [](const Eigen::Vector3d& x, const Eigen::Vector3d& y) {
        return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
      });
      facets->push_back(std::move(pts));
    }
  }
  return {V, int(adjacent.size()), int(std::count(is_class.begin(), is_class.end(), 1))};
}

// The points of x that can be vertices of a sum: the vertices of x's hull by exact predicates
// on the doubles (Epick; a flat or collinear set gives its polygon's or segment's ends), so that
// the oracle hulls |vert A| |vert B| sums instead of |A| |B| (integer grids repeat and bury most).
std::vector<Eigen::Vector3d> hull_vertices(const std::vector<Eigen::Vector3d>& x) {
  std::vector<Epick::Point_3> p;
  for (const auto& v : x) p.emplace_back(v.x(), v.y(), v.z());
  CGAL::Polyhedron_3<Epick> hull;
  CGAL::convex_hull_3(p.begin(), p.end(), hull);
  std::vector<Eigen::Vector3d> out;
  for (auto v = hull.vertices_begin(); v != hull.vertices_end(); ++v)
    out.emplace_back(v->point().x(), v->point().y(), v->point().z());
  return out.empty() ? x : out;
}

// Whether every pairwise sum a + s b is a double exactly (then Epick's exact predicates on the
// doubles decide the structure; else Epeck computes the sums exactly).
bool sums_are_doubles(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s) {
  for (const auto& u : a)
    for (const auto& v : b)
      for (int k = 0; k < 3; ++k) {
        const double x = u[k] + s * v[k], back = x - u[k];
        if (back != s * v[k] || x - back != u[k]) return false;
      }
  return true;
}

}  // namespace

// V, E, F of the exact hull of the pairwise sums a + s b, computed exactly (not rounded to
// double first), with coplanar triangles merged.
ExactCounts exact_counts(const std::vector<Eigen::Vector3d>& a_in, const std::vector<Eigen::Vector3d>& b_in, double s,
                         std::vector<std::vector<Eigen::Vector3d>>* facets) {
  if (sums_are_doubles(a_in, b_in, s)) return exact_structure(a_in, b_in, s, facets);
  const std::vector<Eigen::Vector3d> a = hull_vertices(a_in), b = hull_vertices(b_in);
  // Only sums that can be on the hull go to the exact kernel: the hull of the rounded sums
  // (Epick: exact predicates on those doubles) moves each facet by at most their rounding, so a
  // rounded sum more than 1e-9 of the size inside every one of its facets is inside the exact
  // hull too (its exact hull is the same set's, each point moved by an ulp).
  std::vector<Epick::Point_3> rounded;
  double size = 0;
  for (const auto& u : a)
    for (const auto& v : b) {
      const Eigen::Vector3d x = u + s * v;
      rounded.emplace_back(x.x(), x.y(), x.z());
      size = std::max(size, x.cwiseAbs().maxCoeff());
    }
  CGAL::Polyhedron_3<Epick> hull;
  CGAL::convex_hull_3(rounded.begin(), rounded.end(), hull);
  std::vector<std::pair<Eigen::Vector3d, double>> planes;  // unit normal, offset
  const auto point = [](const Epick::Point_3& q) { return Eigen::Vector3d(q.x(), q.y(), q.z()); };
  for (auto f = hull.facets_begin(); f != hull.facets_end(); ++f) {
    const auto h = f->halfedge();
    const Eigen::Vector3d p0 = point(h->vertex()->point()), p1 = point(h->next()->vertex()->point()),
                          p2 = point(h->next()->next()->vertex()->point());
    const Eigen::Vector3d n = (p1 - p0).cross(p2 - p0).normalized();
    planes.push_back({n, n.dot(p0)});
  }
  const double margin = 1e-9 * std::max(size, 1e-300);
  std::vector<Epeck::Point_3> p;
  for (size_t k = 0; k < rounded.size(); ++k) {
    const Eigen::Vector3d x = point(rounded[k]);
    bool inside = hull.size_of_facets() > 0;
    for (size_t f = 0; f < planes.size() && inside; ++f) inside = planes[f].first.dot(x) < planes[f].second - margin;
    if (inside) continue;
    const Eigen::Vector3d &u = a[k / b.size()], &v = b[k % b.size()];
    p.emplace_back(Epeck::FT(u.x()) + Epeck::FT(s) * Epeck::FT(v.x()),
                     Epeck::FT(u.y()) + Epeck::FT(s) * Epeck::FT(v.y()),
                     Epeck::FT(u.z()) + Epeck::FT(s) * Epeck::FT(v.z()));
  }
  return hull_structure<Epeck>(p, facets);
}

ExactCounts exact_structure(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s,
                            std::vector<std::vector<Eigen::Vector3d>>* facets) {
  if (!sums_are_doubles(a, b, s)) return {-1, -1, -1};
  const std::vector<Eigen::Vector3d> va = hull_vertices(a), vb = hull_vertices(b);
  std::vector<Epick::Point_3> p;
  for (const auto& u : va)
    for (const auto& v : vb) p.emplace_back(u.x() + s * v.x(), u.y() + s * v.y(), u.z() + s * v.z());
  return hull_structure<Epick>(p, facets);
}

double cgal_distance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  using HK = CGAL::Homogeneous<double>;
  using Traits = CGAL::Polytope_distance_d_traits_3<HK, CGAL::Gmpzf, double>;
  std::vector<HK::Point_3> p, q;
  for (const auto& v : a) p.emplace_back(v.x(), v.y(), v.z());
  for (const auto& v : b) q.emplace_back(v.x(), v.y(), v.z());
  CGAL::Polytope_distance_d<Traits> pd(p.begin(), p.end(), q.begin(), q.end());
  return std::sqrt(CGAL::to_double(pd.squared_distance_numerator()) /
                   CGAL::to_double(pd.squared_distance_denominator()));
}

}  // namespace minksum::peers
