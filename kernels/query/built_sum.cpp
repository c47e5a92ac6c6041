// Reading a built sum: whether a point lies in it, and the proximity and penetration of two
// shapes from their difference M = A (-) B. The origin's Voronoi region of M gives the exact
// distance (the paper's Sections 1 and 5.1, Fig. 8); the support pairs of the feature give the
// closest points on A and B, since every point of M is sum_k w_k (a_(i_k) - b_(j_k)) over its
// feature's vertices, and then sum_k w_k a_(i_k) lies on A and sum_k w_k b_(j_k) on B. A
// rounded sum (radius r) is M (+) B(r): a point lies in it within r of M.
#include <minksum/query.hpp>

#include "geometry/closest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Vector3d;

namespace {

// A point of M as weights over (i, j) pairs: its preimages on A and B.
struct Witness {
  double dist2 = std::numeric_limits<double>::infinity();
  int pair[3] = {0, 0, 0};  // indices into the sum's vertices
  double w[3] = {1, 0, 0};
};

// The point of the convex polygon `loop` (vertex indices of m, counter-clockwise about n) that
// is closest to p (m's vertices taken relative to p), with its weights over at most three of
// the polygon's vertices.
Witness closest_on_facet(const MinkowskiSum& m, const Loop& loop, const Vector3d& n,
                         const Vector3d& p = Vector3d::Zero()) {
  const size_t size = size_t(loop.size());
  const auto P = [&](size_t k) -> Vector3d { return m.vertices[loop[int(k % size)]].point - p; };
  const double d = n.dot(P(0));
  const Vector3d q = d * n;  // p projected onto the facet's plane
  bool inside = true;
  for (size_t k = 0; k < size && inside; ++k) inside = (P(k + 1) - P(k)).cross(q - P(k)).dot(n) >= 0;
  Witness best;
  if (inside) {  // the facet's own region: barycentric weights in the fan triangle holding q
    for (size_t k = 1; k + 1 < size; ++k) {
      const Vector3d a = P(0), b = P(k), c = P(k + 1);
      const double area = (b - a).cross(c - a).dot(n);
      const double wb = (q - a).cross(c - a).dot(n) / area, wc = (b - a).cross(q - a).dot(n) / area;
      if (!(wb >= -1e-12 && wc >= -1e-12 && wb + wc <= 1 + 1e-12)) continue;  // NaN (a sliver): skip
      best.dist2 = d * d;
      best.pair[0] = loop[0], best.pair[1] = loop[int(k)], best.pair[2] = loop[int(k + 1)];
      best.w[0] = 1 - wb - wc, best.w[1] = wb, best.w[2] = wc;
      return best;
    }
  }
  // An edge's or a vertex's region: the closest point on the nearest boundary segment.
  for (size_t k = 0; k < size; ++k) {
    const Vector3d a = P(k), e = P(k + 1) - P(k);
    const double t = detail::nearest_on_segment(a, P(k + 1));
    const double dist2 = (a + t * e).squaredNorm();
    if (dist2 < best.dist2) {
      best.dist2 = dist2;
      best.pair[0] = loop[int(k)], best.pair[1] = loop[int((k + 1) % size)], best.pair[2] = loop[0];
      best.w[0] = 1 - t, best.w[1] = t, best.w[2] = 0;
    }
  }
  return best;
}

void witness_points(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, const Witness& w,
                    Vector3d& pa, Vector3d& pb) {
  pa.setZero(), pb.setZero();
  for (int k = 0; k < 3; ++k) {
    pa += w.w[k] * a.vertices[m.vertices[w.pair[k]].i];
    pb += w.w[k] * b.vertices[m.vertices[w.pair[k]].j];
  }
}

void farthest(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out) {
  // The farthest point of a polytope from the origin is one of its vertices.
  int far = 0;
  for (int k = 1; k < m.V; ++k)
    if (m.vertices[k].point.squaredNorm() > m.vertices[far].point.squaredNorm()) far = k;
  out.max_distance = m.vertices[far].point.norm();
  out.far_a = a.vertices[m.vertices[far].i];
  out.far_b = b.vertices[m.vertices[far].j];
}

// The squared distance of p from m (Whole: its loops) where it is at most r, p outside one of
// m's planes: the least distance to the polygons of the facets whose planes p is beyond (one
// of them holds its nearest point), and where that is over r, of those whose planes p is less
// than r inside (a facet farther inside is farther than r). Within rounding of the boundary
// the planes can put p beyond a sliver facet far from it while the facet that holds its
// nearest point has p on its plane.
double distance2_near(const MinkowskiSum& m, const Vector3d& p, double r) {
  double best = std::numeric_limits<double>::infinity();
  if (int(m.loop_start.size()) != m.F + 1) return best;  // (no loops: not a rounded sum the library built)
  for (int pass = 0; pass < 2 && !(best <= r * r); ++pass)
    for (int k = 0; k < m.F; ++k) {
      const double above = m.planes[k].normal.dot(p) - m.planes[k].offset;
      if (pass == 0 ? above > 0 : above <= 0 && above >= -r)
        best = std::min(best, closest_on_facet(m, m.facet(k), m.planes[k].normal, p).dist2);
    }
  return best;
}

// How far the ray from the origin along unit u runs inside M (+) B(r), r = m.radius, the origin
// inside it (else 0): the largest exit of the balls about M's vertices, the cylinders about its
// edges and the slabs over its facets (see detail::ball_exit).
double rounded_exit(const MinkowskiSum& m, const Vector3d& u) {
  const double r = m.radius;
  if (!contains(m, Vector3d::Zero()) || int(m.loop_start.size()) != m.F + 1) return 0;
  double best = 0;
  for (const SumVertex& v : m.vertices) best = std::max(best, detail::ball_exit(v.point, u, r));
  if (m.F == 0 && m.V == 2)  // a segment core
    best = std::max(best, detail::cylinder_exit(m.vertices[0].point, m.vertices[1].point, u, r));
  for (int k = 0; k < m.F; ++k) {
    const Loop f = m.facet(k);
    const auto corner = [&](int e) { return m.vertices[f[e]].point; };
    for (int e = 0; e < f.size(); ++e)  // (each edge twice, once per facet: the same exit)
      best = std::max(best, detail::cylinder_exit(corner(e), corner((e + 1) % f.size()), u, r));
    best = std::max(best, detail::slab_exit(corner, f.size(), m.planes[k].normal, m.planes[k].offset, u, r));
  }
  return best;
}

// The squared distance of p from a sum without facets: a rounded sum's point or segment core.
double distance2_to_edge(const MinkowskiSum& m, const Vector3d& p) {
  const Vector3d a = m.vertices.front().point - p, b = m.vertices.back().point - p;
  return (a + detail::nearest_on_segment(a, b) * (b - a)).squaredNorm();
}

}  // namespace

bool contains(const MinkowskiSum& m, const Vector3d& p) {
  if (m.vertices.empty()) return false;  // (a failed sum is empty: nothing lies in it)
  if (m.planes.empty()) return distance2_to_edge(m, p) <= m.radius * m.radius;  // (NaN: false)
  if (m.F == 2 && int(m.loop_start.size()) == 3)  // a rounded sum's polygon: its sides' planes hold no edge
    return closest_on_facet(m, m.facet(0), m.planes[0].normal, p).dist2 <= m.radius * m.radius;
  bool inside = true;
  for (const auto& plane : m.planes) {
    const double above = plane.normal.dot(p) - plane.offset;
    if (!(above <= m.radius)) return false;  // (a NaN point is in nothing)
    inside = inside && above <= 0;
  }
  return inside || distance2_near(m, p, m.radius) <= m.radius * m.radius;
}

Status proximity(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out) {
  out = Proximity{};
  if (m.radius > 0) return Status::Unsupported;  // (how the radius splits between a and b is not known here)
  if (m.F < 4 || m.V < 4 || int(m.planes.size()) != m.F || int(m.vertices.size()) != m.V) return Status::TooFewPoints;
  for (const SumVertex& v : m.vertices)
    if (v.i < 0 || v.j < 0 || size_t(v.i) >= a.vertices.size() || size_t(v.j) >= b.vertices.size())
      return Status::InvalidMesh;
  farthest(m, a, b, out);
  // Inside M (every offset >= 0): intersecting; the nearest facet is the minimum translation.
  // Within rounding of the boundary (offsets are exact only to a few ulps of M's size) the
  // origin touches M: there a plane can separate it by rounding while its facet lies far away,
  // and the facet that holds the origin's projection may not separate it.
  double size = 0;
  for (const auto& v : m.vertices) size = std::max(size, v.point.cwiseAbs().maxCoeff());
  const double tol = 64 * std::numeric_limits<double>::epsilon() * size;
  int nearest = 0;
  for (int k = 1; k < m.F; ++k)
    if (m.planes[k].offset < m.planes[nearest].offset) nearest = k;
  if (m.planes[nearest].offset >= -tol) {
    out.intersecting = true;
    out.penetration_depth = std::max(0.0, m.planes[nearest].offset);
    out.penetration_direction = m.planes[nearest].normal;
    // Deepest points: the origin's projection onto that facet, pulled back to A and B.
    witness_points(m, a, b, closest_on_facet(m, m.facet(nearest), m.planes[nearest].normal), out.point_a, out.point_b);
    return Status::Ok;
  }
  // Outside: the closest point of M lies on a facet whose plane separates the origin.
  Witness best;
  for (int k = 0; k < m.F; ++k) {
    if (m.planes[k].offset >= tol) continue;
    const Witness w = closest_on_facet(m, m.facet(k), m.planes[k].normal);
    if (w.dist2 < best.dist2) best = w;
  }
  out.distance = std::sqrt(best.dist2);
  witness_points(m, a, b, best, out.point_a, out.point_b);
  return Status::Ok;
}

double penetration_along(const MinkowskiSum& m, const Vector3d& u) {
  if (m.radius > 0) return rounded_exit(m, u);
  // The ray from the origin along u leaves M through the first plane it crosses.
  double t = std::numeric_limits<double>::infinity();
  for (const auto& p : m.planes) {
    if (p.offset < 0) return 0;  // the origin is outside M: no overlap
    const double along = p.normal.dot(u);
    if (along > 0) t = std::min(t, p.offset / along);
  }
  return std::isfinite(t) ? t : 0;
}

}  // namespace minksum
