#include "checks.hpp"

#include "support/cgal_peer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <filesystem>
#include <map>
#include <random>
#include <set>

namespace minksum::test {

using Eigen::Vector3d;

std::vector<Vector3d> pairwise(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s) {
  std::vector<Vector3d> out;
  for (const auto& p : a)
    for (const auto& q : b) out.push_back(p + s * q);
  return out;
}

namespace {
double max_dot(const std::vector<Vector3d>& pts, const Vector3d& n) {
  double h = -1e300;
  for (const auto& p : pts) h = std::max(h, n.dot(p));
  return h;
}
}  // namespace

testing::AssertionResult valid_sum(const std::vector<Vector3d>& a_pts, const std::vector<Vector3d>& b_pts, double s,
                                   const ConvexPolytope& A, const ConvexPolytope& B, const MinkowskiSum& m, double tol,
                                   double support_tol, int directions, unsigned seed) {
  const auto sums = pairwise(a_pts, b_pts, s);
  // Rounding errors scale with the inputs' coordinates, which may dwarf the result (A (-) A).
  double size = 0;
  for (const auto* set : {&a_pts, &b_pts, &sums})
    for (const auto& p : *set) size = std::max(size, p.cwiseAbs().maxCoeff());
  if (m.F + 1 != int(m.loop_start.size()) || m.F != int(m.planes.size()) || m.V != int(m.vertices.size()) ||
      m.loop_start[0] != 0 || m.loop_start.back() != int(m.loop_vertex.size()) || 2 * m.E != int(m.loop_vertex.size()))
    return testing::AssertionFailure() << "counts do not match the arrays";
  if (!m.euler_ok || m.V - m.E + m.F != 2)
    return testing::AssertionFailure() << "Euler fails: V=" << m.V << " E=" << m.E << " F=" << m.F;
  for (const auto& v : m.vertices) {
    if (!v.point.allFinite()) return testing::AssertionFailure() << "non-finite vertex";
    const Vector3d expect = a_pts[A.input_index[v.i]] + s * b_pts[B.input_index[v.j]];
    if (v.point != expect)
      return testing::AssertionFailure() << "vertex (" << v.i << "," << v.j << ") is not a_i + s b_j";
  }
  for (int f = 0; f < m.F; ++f) {
    const auto& pl = m.planes[f];
    if (!pl.normal.allFinite() || std::abs(pl.normal.norm() - 1) > 1e-12 || !std::isfinite(pl.offset))
      return testing::AssertionFailure() << "facet " << f << " has a bad plane";
    for (const auto& p : sums)
      if (pl.normal.dot(p) > pl.offset + tol * size)
        return testing::AssertionFailure()
               << "a pairwise sum is outside facet " << f << " by " << pl.normal.dot(p) - pl.offset;
    Vector3d newell = Vector3d::Zero();
    const Loop loop = m.facet(f);
    if (loop.size() < 3) return testing::AssertionFailure() << "facet " << f << " has fewer than 3 vertices";
    for (int k = 0; k < loop.size(); ++k) {
      if (loop[k] < 0 || loop[k] >= m.V) return testing::AssertionFailure() << "facet " << f << " has a bad index";
      const Vector3d& p = m.vertices[loop[k]].point;
      newell += p.cross(m.vertices[loop[(k + 1) % loop.size()]].point);
      if (std::abs(pl.normal.dot(p) - pl.offset) > tol * size)
        return testing::AssertionFailure() << "vertex off the plane of facet " << f;
    }
    // (A sliver facet's area may be below the rounding of its Newell sum, about eps size^2 per
    // term: its orientation is not measurable there, only its plane.)
    if (newell.dot(pl.normal) <= 0 && newell.norm() > 1e-14 * loop.size() * size * size)
      return testing::AssertionFailure() << "facet " << f << " loop is not counter-clockwise";
    const auto& first = m.vertices[loop[0]];
    if (first.i != pl.i || first.j != pl.j)
      return testing::AssertionFailure() << "plane pair is not its loop's first vertex";
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vector3d> verts;
  for (const auto& v : m.vertices) verts.push_back(v.point);
  std::vector<Vector3d> neg_b;
  for (const auto& q : b_pts) neg_b.push_back(s * q);
  std::vector<Vector3d> probes;
  for (int k = 0; k < directions; ++k) probes.push_back(Vector3d(g(rng), g(rng), g(rng)).normalized());
  // And at every facet normal the exact sum can have (A's and B's face normals, the crosses of
  // an edge of A with an edge of B; both signs), where a vertex with a tiny normal cone is
  // extreme and random directions rarely land; where that set is small enough to afford.
  if (A.edges.size() * B.edges.size() <= 4000) {
    for (const auto* p : {&A, &B})
      for (const Face& f : p->faces) probes.push_back(f.normal), probes.push_back(-f.normal);
    for (const Edge& e : A.edges)
      for (const Edge& f : B.edges) {
        const Vector3d da = A.vertices[e.v1] - A.vertices[e.v0], db = B.vertices[f.v1] - B.vertices[f.v0];
        const Vector3d c = da.cross(db);
        if (c.norm() > 1e-9 * da.norm() * db.norm())
          probes.push_back(c.normalized()), probes.push_back(-c.normalized());
      }
  }
  for (const Vector3d& n : probes) {
    const double expect = max_dot(a_pts, n) + max_dot(neg_b, n);
    const double got = max_dot(verts, n);
    if (std::abs(got - expect) > support_tol * std::max(size, 1e-300))
      return testing::AssertionFailure() << "support error " << got - expect << " in direction " << n.transpose();
  }
  return testing::AssertionSuccess();
}

testing::AssertionResult same_sum(const MinkowskiSum& x, const MinkowskiSum& y, double tol) {
  if (x.V != y.V || x.E != y.E || x.F != y.F)
    return testing::AssertionFailure() << "V/E/F " << x.V << "/" << x.E << "/" << x.F << " vs " << y.V << "/" << y.E
                                       << "/" << y.F;
  double size = 0;
  for (const auto& v : x.vertices) size = std::max(size, v.point.cwiseAbs().maxCoeff());
  auto pairs = [](const MinkowskiSum& m, size_t f) {
    std::set<std::pair<int, int>> s;
    for (int k : m.facet(int(f))) s.insert({m.vertices[k].i, m.vertices[k].j});
    return s;
  };
  // Facets match when they have the same vertex pairs and each one's vertices lie on the other's
  // plane within tol * size. (The normal of a sliver spanned by nearly parallel edges is
  // ill-conditioned; its plane through the vertices is not.)
  auto off_plane = [&](const MinkowskiSum& m, size_t f, const SumPlane& p) {
    double worst = 0;
    for (int k : m.facet(int(f))) worst = std::max(worst, std::abs(p.normal.dot(m.vertices[k].point) - p.offset));
    return worst;
  };
  std::map<std::set<std::pair<int, int>>, size_t> by_pairs;
  for (size_t g = 0; g < y.planes.size(); ++g) by_pairs.emplace(pairs(y, g), g);
  for (size_t f = 0; f < x.planes.size(); ++f) {
    auto it = by_pairs.find(pairs(x, f));
    if (it == by_pairs.end()) {
      auto r = testing::AssertionFailure();
      r << "facet " << f << " (n = " << x.planes[f].normal.transpose() << ") has no facet with the same vertex pairs:";
      for (const auto& p : pairs(x, f)) r << " (" << p.first << "," << p.second << ")";
      for (size_t g = 0; g < y.planes.size(); ++g)
        if ((y.planes[g].normal - x.planes[f].normal).norm() < 1e-6) {
          r << "; the other has n = " << y.planes[g].normal.transpose() << " with";
          for (const auto& p : pairs(y, g)) r << " (" << p.first << "," << p.second << ")";
        }
      return r;
    }
    const size_t g = it->second;
    const double d = std::max(off_plane(x, f, y.planes[g]), off_plane(y, g, x.planes[f]));
    if (d > tol * std::max(size, 1.0))
      return testing::AssertionFailure() << "facet " << f << " (n = " << x.planes[f].normal.transpose()
                                         << "): the planes differ by " << d << " at its vertices";
  }
  return testing::AssertionSuccess();
}

std::vector<ExactFacet> exact_hull(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                   peers::ExactCounts* counts) {
  std::vector<std::vector<Vector3d>> facets;
  const peers::ExactCounts e = peers::exact_counts(a, b, s, &facets);
  if (counts) *counts = e;
  Vector3d centre = Vector3d::Zero();
  int n = 0;
  for (const auto& f : facets)
    for (const auto& p : f) centre += p, ++n;
  centre /= std::max(n, 1);
  std::vector<ExactFacet> out;
  for (auto& f : facets) {
    // The normal: the longest cross product of two spokes from one vertex (the vertices are
    // sorted, not in loop order); outward: away from the centre of all vertices.
    Vector3d best = Vector3d::Zero();
    for (size_t i = 1; i < f.size(); ++i)
      for (size_t j = i + 1; j < f.size(); ++j) {
        const Vector3d c = (f[i] - f[0]).cross(f[j] - f[0]);
        if (c.squaredNorm() > best.squaredNorm()) best = c;
      }
    ExactFacet e{best.normalized(), 0, std::move(f)};
    e.offset = e.normal.dot(e.points[0]);
    if (e.normal.dot(centre) > e.offset) e.normal = -e.normal, e.offset = -e.offset;
    out.push_back(std::move(e));
  }
  return out;
}

testing::AssertionResult equals_exact_hull(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                           const MinkowskiSum& m, double tol) {
  std::vector<std::vector<Vector3d>> facets;
  const peers::ExactCounts e = peers::exact_counts(a, b, s, &facets);
  if (m.V != e.V || m.E != e.E || m.F != e.F)
    return testing::AssertionFailure() << "V, E, F " << m.V << "/" << m.E << "/" << m.F << ", exact " << e.V << "/"
                                       << e.E << "/" << e.F;
  double size = 1;
  for (const auto& v : m.vertices) size = std::max(size, v.point.cwiseAbs().maxCoeff());
  const double within = tol * size;
  // Each exact vertex names the one vertex of m within `within` of it (by x, then the rest).
  std::vector<std::pair<double, int>> by_x;
  for (int k = 0; k < int(m.vertices.size()); ++k) by_x.push_back({m.vertices[k].point.x(), k});
  std::sort(by_x.begin(), by_x.end());
  auto vertex_of = [&](const Vector3d& p) {
    int found = -1;
    for (auto it = std::lower_bound(by_x.begin(), by_x.end(), std::pair<double, int>{p.x() - within, -1});
         it != by_x.end() && it->first <= p.x() + within; ++it)
      if ((m.vertices[it->second].point - p).cwiseAbs().maxCoeff() <= within) {
        if (found >= 0) return -2;
        found = it->second;
      }
    return found;
  };
  std::multiset<std::vector<int>> exact, ours;
  for (const auto& f : facets) {
    std::vector<int> ids;
    for (const auto& p : f) {
      const int k = vertex_of(p);
      if (k < 0)
        return testing::AssertionFailure() << "the exact vertex " << p.transpose()
                                           << (k == -1 ? " is not" : " is more than one") << " vertex of the sum";
      ids.push_back(k);
    }
    std::sort(ids.begin(), ids.end());
    exact.insert(std::move(ids));
  }
  for (int f = 0; f < m.F; ++f) {
    std::vector<int> ids(m.facet(f).begin(), m.facet(f).end());
    std::sort(ids.begin(), ids.end());
    ours.insert(std::move(ids));
  }
  if (exact != ours) return testing::AssertionFailure() << "a facet has other vertices than the exact one";
  return testing::AssertionSuccess();
}

namespace {

// The largest |coordinate| of the exact facets' vertices, at least 1.
double exact_size(const std::vector<ExactFacet>& exact) {
  double size = 1;
  for (const auto& f : exact)
    for (const auto& p : f.points) size = std::max(size, p.cwiseAbs().maxCoeff());
  return size;
}

// m's planes against the exact facets: one distinct plane per exact facet, holding its vertices
// within `within`, each plane's pair a_i + s b_j on it.
testing::AssertionResult planes_match(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                      const MinkowskiSum& m, const std::vector<ExactFacet>& exact, double within) {
  if (m.F != int(exact.size()) || int(m.planes.size()) != m.F)
    return testing::AssertionFailure() << "F " << m.F << " (" << m.planes.size() << " planes), exact " << exact.size();
  // Which planes support the exact hull and hold each exact facet's vertices; then a perfect
  // matching of facets to planes (Kuhn's augmenting paths): the two planes of a sliver and its
  // neighbour, parallel to an ulp where the operands' sides are rounded from parallel ones, both
  // hold both facets' vertices. (Supporting the hull, not a facet normal from the rounded
  // vertices, tells a plane's side: an ulp-wide sliver's rounded vertices are collinear.)
  std::vector<char> supports(m.planes.size(), 1);
  for (int k = 0; k < m.F; ++k)
    for (const auto& f : exact)
      for (const auto& p : f.points)
        if (m.planes[size_t(k)].normal.dot(p) - m.planes[size_t(k)].offset > within) supports[size_t(k)] = 0;
  std::vector<std::vector<int>> holds(exact.size());
  for (size_t e = 0; e < exact.size(); ++e) {
    const ExactFacet& f = exact[e];
    for (int k = 0; k < m.F; ++k) {
      const SumPlane& q = m.planes[size_t(k)];
      bool on = supports[size_t(k)];
      for (size_t v = 0; v < f.points.size() && on; ++v) on = std::abs(q.normal.dot(f.points[v]) - q.offset) <= within;
      if (on) holds[e].push_back(k);
    }
    if (holds[e].empty()) return testing::AssertionFailure() << "no plane holds the exact facet at " << f.normal.transpose();
  }
  std::vector<int> facet_of(m.planes.size(), -1);
  std::vector<char> seen;
  const std::function<bool(int)> augment = [&](int e) {
    for (int k : holds[size_t(e)]) {
      if (seen[size_t(k)]) continue;
      seen[size_t(k)] = 1;
      if (facet_of[size_t(k)] < 0 || augment(facet_of[size_t(k)])) return facet_of[size_t(k)] = e, true;
    }
    return false;
  };
  for (int e = 0; e < int(exact.size()); ++e) {
    seen.assign(m.planes.size(), 0);
    if (!augment(e)) return testing::AssertionFailure() << "the exact facet at " << exact[size_t(e)].normal.transpose()
                                                       << " has no plane of its own";
  }
  for (int k = 0; k < m.F; ++k) {
    const SumPlane& q = m.planes[size_t(k)];
    if (facet_of[size_t(k)] < 0) return testing::AssertionFailure() << "plane " << k << " holds no exact facet";
    if (std::abs(q.normal.norm() - 1) > 1e-12) return testing::AssertionFailure() << "plane " << k << " is not unit";
    if (q.i < 0 || q.j < 0 || q.i >= int(a.size()) || q.j >= int(b.size()))
      return testing::AssertionFailure() << "plane " << k << " has no support pair";
    if (std::abs(q.normal.dot(a[size_t(q.i)] + s * b[size_t(q.j)]) - q.offset) > within)
      return testing::AssertionFailure() << "plane " << k << "'s pair (" << q.i << ", " << q.j << ") is off it";
  }
  return testing::AssertionSuccess();
}

}  // namespace

testing::AssertionResult equals_exact_planes(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                             const MinkowskiSum& m, double tol) {
  if (m.parts != SumParts::Planes || !m.vertices.empty() || !m.loop_vertex.empty())
    return testing::AssertionFailure() << "not a planes-only sum";
  const std::vector<ExactFacet> exact = exact_hull(a, b, s);
  return planes_match(a, b, s, m, exact, tol * exact_size(exact));
}

testing::AssertionResult equals_exact_vertices(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b,
                                               double s, const MinkowskiSum& m, double tol) {
  if (m.parts != SumParts::Vertices || !m.loop_start.empty() || !m.loop_vertex.empty())
    return testing::AssertionFailure() << "not a vertices-level sum";
  peers::ExactCounts e;
  const std::vector<ExactFacet> exact = exact_hull(a, b, s, &e);
  if (m.V != e.V || m.E != e.E || m.F != e.F || int(m.vertices.size()) != m.V || !m.euler_ok)
    return testing::AssertionFailure() << "V/E/F " << m.V << "/" << m.E << "/" << m.F << " (" << m.vertices.size()
                                       << " vertices), exact " << e.V << "/" << e.E << "/" << e.F;
  const double within = tol * exact_size(exact);
  // Every vertex is its pair's point, in (i, j) order, near an exact vertex, and each exact
  // vertex near one of them (with V equal: the same points, but where an ulp-wide sliver puts
  // two within the tolerance).
  for (int v = 0; v < m.V; ++v) {
    const SumVertex& x = m.vertices[size_t(v)];
    if (x.i < 0 || x.j < 0 || x.i >= int(a.size()) || x.j >= int(b.size()) ||
        (x.point - (a[size_t(x.i)] + s * b[size_t(x.j)])).cwiseAbs().maxCoeff() > within)
      return testing::AssertionFailure() << "vertex " << v << " is not its pair's point";
    if (v > 0 && std::make_pair(m.vertices[size_t(v) - 1].i, m.vertices[size_t(v) - 1].j) >= std::make_pair(x.i, x.j))
      return testing::AssertionFailure() << "vertex " << v << " is out of (i, j) order";
  }
  const auto near = [within](const Vector3d& p, const Vector3d& q) { return (p - q).cwiseAbs().maxCoeff() <= within; };
  for (const auto& f : exact)
    for (const Vector3d& p : f.points)
      if (std::none_of(m.vertices.begin(), m.vertices.end(), [&](const SumVertex& x) { return near(x.point, p); }))
        return testing::AssertionFailure() << "no vertex at the exact vertex " << p.transpose();
  for (const SumVertex& x : m.vertices) {
    bool found = false;
    for (const auto& f : exact)
      found = found || std::any_of(f.points.begin(), f.points.end(), [&](const Vector3d& p) { return near(x.point, p); });
    if (!found) return testing::AssertionFailure() << "the vertex " << x.point.transpose() << " is not an exact one";
  }
  return planes_match(a, b, s, m, exact, within);
}

// Closest points of segments [p0, p1] and [q0, q1] (Ericson, Real-Time Collision Detection 5.1.9).
double segment_distance(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0, const Vector3d& q1) {
  const Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a <= 1e-300 && e <= 1e-300) return r.norm();
  if (a <= 1e-300) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e <= 1e-300) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2), denom = a * e - b * b;
      s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0)
        t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      else if (t > 1)
        t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  return (p0 + s * d1 - (q0 + t * d2)).norm();
}

namespace {
// Distance from p to the convex polygon `loop` of `v` with unit normal n.
double point_polygon(const Vector3d& p, const std::vector<Vector3d>& v, const std::vector<int>& loop,
                     const Vector3d& n) {
  const double h = n.dot(p - v[loop[0]]);
  const Vector3d q = p - h * n;
  bool inside = true;
  for (size_t k = 0; k < loop.size(); ++k)
    inside = inside && (v[loop[(k + 1) % loop.size()]] - v[loop[k]]).cross(q - v[loop[k]]).dot(n) >= 0;
  if (inside) return std::abs(h);
  double best = 1e300;
  for (size_t k = 0; k < loop.size(); ++k)
    best = std::min(best, segment_distance(p, p, v[loop[k]], v[loop[(k + 1) % loop.size()]]));
  return best;
}
}  // namespace

ConvexPolytope transformed(const ConvexPolytope& p, const Eigen::Isometry3d& pose) {
  ConvexPolytope q = p;
  for (auto& v : q.vertices) v = pose * v;
  for (auto& f : q.faces) {
    f.normal = (pose.linear() * f.normal).normalized();
    f.offset = f.normal.dot(q.vertices[size_t(f.loop[0])]);
  }
  return q;
}

Oracle brute_force(const ConvexPolytope& A, const ConvexPolytope& B) {
  Oracle o{false, 1e300, 1e300, 0};
  // SAT: face normals of both and all edge crosses; the smallest overlap is the exact depth.
  std::vector<Vector3d> axes;
  for (const auto* P : {&A, &B})
    for (const auto& f : P->faces) axes.push_back(f.normal);
  for (const auto& ea : A.edges)
    for (const auto& eb : B.edges) {
      const Vector3d c = (A.vertices[ea.v1] - A.vertices[ea.v0]).cross(B.vertices[eb.v1] - B.vertices[eb.v0]);
      if (c.norm() > 1e-9) axes.push_back(c.normalized());
    }
  double min_overlap = 1e300;
  for (const auto& n : axes) {
    double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
    for (const auto& p : A.vertices) amin = std::min(amin, n.dot(p)), amax = std::max(amax, n.dot(p));
    for (const auto& p : B.vertices) bmin = std::min(bmin, n.dot(p)), bmax = std::max(bmax, n.dot(p));
    min_overlap = std::min(min_overlap, std::min(amax - bmin, bmax - amin));
  }
  o.overlap = min_overlap >= 0;
  o.depth = o.overlap ? min_overlap : 0;
  o.distance = 0;
  if (!o.overlap) {
    o.distance = 1e300;
    for (const auto& p : A.vertices)
      for (const auto& f : B.faces) o.distance = std::min(o.distance, point_polygon(p, B.vertices, f.loop, f.normal));
    for (const auto& p : B.vertices)
      for (const auto& f : A.faces) o.distance = std::min(o.distance, point_polygon(p, A.vertices, f.loop, f.normal));
    for (const auto& ea : A.edges)
      for (const auto& eb : B.edges)
        o.distance = std::min(
            o.distance, segment_distance(A.vertices[ea.v0], A.vertices[ea.v1], B.vertices[eb.v0], B.vertices[eb.v1]));
  }
  for (const auto& p : A.vertices)
    for (const auto& q : B.vertices) o.max_distance = std::max(o.max_distance, (p - q).norm());
  return o;
}

std::string data_path(const std::string& name) {
  return (std::filesystem::path(MINKSUM_SOURCE_DIR) / ".." / "shared" / "data" / name).string();
}

tools::Mesh test_mesh(const std::string& name, int fallback_rings) {
  const std::filesystem::path path = data_path(name);
  tools::Mesh m;
  std::string error;
  if (std::filesystem::exists(path) && tools::read_mesh(path.string(), m, error)) return m;
  return tools::bumpy_sphere(fallback_rings);
}

Eigen::Isometry3d random_pose(std::mt19937_64& rng, double reach) {
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::Quaterniond q(u(rng), u(rng), u(rng), u(rng));
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear() = q.normalized().toRotationMatrix();
  p.translation() = reach * Vector3d(u(rng), u(rng), u(rng));
  return p;
}

bool sums_are_doubles(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s) {
  for (const auto& p : a)
    for (const auto& q : b)
      for (int d = 0; d < 3; ++d) {
        const double x = p[d], y = s * q[d], sum = x + y, yv = sum - x, xv = sum - yv;
        if ((x - xv) + (y - yv) != 0) return false;
      }
  return true;
}

int scaled(int n, int at_least) {
  const char* s = std::getenv("MINKSUM_TEST_SCALE");
  const double f = s ? std::atof(s) : 1.0;
  return std::max(at_least, int(n * (f > 0 ? f : 1.0)));
}

std::unique_ptr<MeshSetup> mesh_setup(const std::string& name, int fallback_rings) {
  auto m = std::make_unique<MeshSetup>();
  m->mesh = test_mesh(name, fallback_rings);
  EXPECT_EQ(build_octree(m->mesh.vertices, m->mesh.triangles, m->tree), Status::Ok);
  make_workspace(m->tree, m->tree, m->ws);
  return m;
}

}  // namespace minksum::test
