// CGAL as a peer and the exact oracle of the sums, in this one translation unit (CGAL is slow to
// compile): convex_hull_3 on the pairwise sums (the paper's comparator), the exact Minkowski sum
// of Nef polyhedra (minkowski_sum_3), and the exact facet structure of a sum.
#include "cgal_peer.hpp"

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>
#include <CGAL/minkowski_sum_3.h>

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

int cgal_nef_sum(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  const auto nef = [](const std::vector<Eigen::Vector3d>& pts) {
    std::vector<Epeck::Point_3> p;
    for (const auto& v : pts) p.emplace_back(v.x(), v.y(), v.z());
    CGAL::Polyhedron_3<Epeck> hull;
    CGAL::convex_hull_3(p.begin(), p.end(), hull);
    return CGAL::Nef_polyhedron_3<Epeck>(hull);
  };
  CGAL::Nef_polyhedron_3<Epeck> A = nef(a), B = nef(b);
  const CGAL::Nef_polyhedron_3<Epeck> sum = CGAL::minkowski_sum_3(A, B);
  return int(sum.number_of_vertices());
}

// V, E, F of the exact hull of the pairwise sums a + s b, computed exactly (not rounded to
// double first), with coplanar triangles merged (union-find over facets).
ExactCounts exact_counts(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s) {
  std::vector<Epeck::Point_3> p;
  for (const auto& u : a)
    for (const auto& v : b)
      p.emplace_back(Epeck::FT(u.x()) + Epeck::FT(s) * Epeck::FT(v.x()), Epeck::FT(u.y()) + Epeck::FT(s) * Epeck::FT(v.y()),
                     Epeck::FT(u.z()) + Epeck::FT(s) * Epeck::FT(v.z()));
  CGAL::Polyhedron_3<Epeck> hull;
  CGAL::convex_hull_3(p.begin(), p.end(), hull);
  std::map<CGAL::Polyhedron_3<Epeck>::Facet_const_handle, int> id;
  for (auto f = hull.facets_begin(); f != hull.facets_end(); ++f) id.emplace(f, int(id.size()));
  std::vector<int> parent(id.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (auto h = hull.halfedges_begin(); h != hull.halfedges_end(); ++h) {
    const auto& a = h->vertex()->point();
    const auto& b = h->opposite()->vertex()->point();
    const auto& c = h->next()->vertex()->point();
    const auto& d = h->opposite()->next()->vertex()->point();
    if (CGAL::coplanar(a, b, c, d)) parent[find(id[h->facet()])] = find(id[h->opposite()->facet()]);
  }
  std::set<int> classes;
  std::set<std::pair<int, int>> adjacent;
  for (auto h = hull.halfedges_begin(); h != hull.halfedges_end(); ++h) {
    const int x = find(id[h->facet()]), y = find(id[h->opposite()->facet()]);
    classes.insert(x);
    if (x != y) adjacent.insert({std::min(x, y), std::max(x, y)});
  }
  int V = 0;  // a true vertex touches at least three merged facets
  for (auto v = hull.vertices_begin(); v != hull.vertices_end(); ++v) {
    std::set<int> around;
    auto h = v->vertex_begin();
    do around.insert(find(id[h->facet()])); while (++h != v->vertex_begin());
    V += around.size() >= 3;
  }
  return {V, int(adjacent.size()), int(classes.size())};
}

}  // namespace minksum::peers
