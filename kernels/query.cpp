// Proximity queries on M = A (-) B: the origin's Voronoi region of M gives the exact distance
// (the paper's Sections 1 and 5.1, Fig. 8); the support pairs of the feature give the closest
// points on A and B, since every point of M is sum_k w_k (a_(i_k) - b_(j_k)) over its feature's
// vertices, and then sum_k w_k a_(i_k) lies on A and sum_k w_k b_(j_k) on B.
#include <minksum/query.hpp>


#include <minksum/kernels.hpp>

#include "box_pair.hpp"

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
// is closest to the origin, with its weights over at most three of the polygon's vertices.
Witness closest_on_facet(const MinkowskiSum& m, const std::vector<int>& loop, const Vector3d& n) {
  const auto P = [&](size_t k) -> const Vector3d& { return m.vertices[loop[k % loop.size()]].point; };
  const double d = n.dot(P(0));
  const Vector3d q = d * n;  // the origin projected onto the facet's plane
  bool inside = true;
  for (size_t k = 0; k < loop.size() && inside; ++k)
    inside = (P(k + 1) - P(k)).cross(q - P(k)).dot(n) >= 0;
  Witness best;
  if (inside) {  // the facet's own region: barycentric weights in the fan triangle holding q
    for (size_t k = 1; k + 1 < loop.size(); ++k) {
      const Vector3d &a = P(0), &b = P(k), &c = P(k + 1);
      const double area = (b - a).cross(c - a).dot(n);
      const double wb = (q - a).cross(c - a).dot(n) / area, wc = (b - a).cross(q - a).dot(n) / area;
      if (!(wb >= -1e-12 && wc >= -1e-12 && wb + wc <= 1 + 1e-12)) continue;  // NaN (a sliver): skip
      best.dist2 = d * d;
      best.pair[0] = loop[0], best.pair[1] = loop[k], best.pair[2] = loop[k + 1];
      best.w[0] = 1 - wb - wc, best.w[1] = wb, best.w[2] = wc;
      return best;
    }
  }
  // An edge's or a vertex's region: the closest point on the nearest boundary segment.
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d &a = P(k), e = P(k + 1) - P(k);
    const double len2 = e.squaredNorm();
    const double t = len2 > 0 ? std::clamp(-a.dot(e) / len2, 0.0, 1.0) : 0.0;
    const double dist2 = (a + t * e).squaredNorm();
    if (dist2 < best.dist2) {
      best.dist2 = dist2;
      best.pair[0] = loop[k], best.pair[1] = loop[(k + 1) % loop.size()], best.pair[2] = loop[0];
      best.w[0] = 1 - t, best.w[1] = t, best.w[2] = 0;
    }
  }
  return best;
}

void witness_points(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b,
                    const Witness& w, Vector3d& pa, Vector3d& pb) {
  pa.setZero(), pb.setZero();
  for (int k = 0; k < 3; ++k) {
    pa += w.w[k] * a.vertices[m.vertices[w.pair[k]].i];
    pb += w.w[k] * b.vertices[m.vertices[w.pair[k]].j];
  }
}

void farthest(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b,
              Proximity& out) {
  // The farthest point of a polytope from the origin is one of its vertices.
  int far = 0;
  for (int k = 1; k < m.V; ++k)
    if (m.vertices[k].point.squaredNorm() > m.vertices[far].point.squaredNorm()) far = k;
  out.max_distance = m.vertices[far].point.norm();
  out.far_a = a.vertices[m.vertices[far].i];
  out.far_b = b.vertices[m.vertices[far].j];
}

}  // namespace

bool contains(const MinkowskiSum& m, const Vector3d& p) {
  for (const auto& plane : m.planes)
    if (plane.normal.dot(p) > plane.offset) return false;
  return true;
}

Proximity proximity(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b) {
  Proximity out;
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
    witness_points(m, a, b, closest_on_facet(m, m.facets[nearest], m.planes[nearest].normal),
                   out.point_a, out.point_b);
    return out;
  }
  // Outside: the closest point of M lies on a facet whose plane separates the origin.
  Witness best;
  for (int k = 0; k < m.F; ++k) {
    if (m.planes[k].offset >= tol) continue;
    const Witness w = closest_on_facet(m, m.facets[k], m.planes[k].normal);
    if (w.dist2 < best.dist2) best = w;
  }
  out.distance = std::sqrt(best.dist2);
  witness_points(m, a, b, best, out.point_a, out.point_b);
  return out;
}

double penetration_along(const MinkowskiSum& m, const Vector3d& u) {
  // The ray from the origin along u leaves M through the first plane it crosses.
  double t = std::numeric_limits<double>::infinity();
  for (const auto& p : m.planes) {
    if (p.offset < 0) return 0;  // the origin is outside M: no overlap
    const double along = p.normal.dot(u);
    if (along > 0) t = std::min(t, p.offset / along);
  }
  return std::isfinite(t) ? t : 0;
}

namespace {

// Two coplanar flat operands: M is a flat polygon, which the result type does not describe.
// Its proximity is that of the polygon of the pairwise differences (a flat polytope).
Status flat_proximity(const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out) {
  std::vector<Vector3d> diffs;
  for (const auto& p : a.vertices)
    for (const auto& q : b.vertices) diffs.push_back(p - q);
  ConvexPolytope poly;
  const Status s = polytope_from_points(diffs, poly);
  if (s != Status::Ok) return s;
  // Present the polygon as a two-sided "sum" so that the facet routines apply unchanged.
  MinkowskiSum m;
  const int nb = int(b.vertices.size());
  for (size_t k = 0; k < poly.vertices.size(); ++k)
    m.vertices.push_back({poly.input_index[k] / nb, poly.input_index[k] % nb, poly.vertices[k]});
  m.V = int(m.vertices.size());
  for (const auto& f : poly.faces) {
    m.facets.push_back(f.loop);
    m.planes.push_back({f.normal, f.offset, -1, -1});
  }
  m.F = int(m.facets.size());
  out = Proximity{};
  farthest(m, a, b, out);
  const Witness w = closest_on_facet(m, m.facets[0], m.planes[0].normal);
  witness_points(m, a, b, w, out.point_a, out.point_b);
  // On the polygon (to rounding): they touch; any move along the normal separates them.
  double size = 0;
  for (const auto& v : m.vertices) size = std::max(size, v.point.cwiseAbs().maxCoeff());
  if (std::sqrt(w.dist2) <= 1e-12 * size) {
    out.intersecting = true;
    out.penetration_direction = m.planes[0].normal;
  } else {
    out.distance = std::sqrt(w.dist2);
  }
  return Status::Ok;
}

}  // namespace

Status proximity(const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out) {
  MinkowskiSum m;
  const Status s = minkowski_difference(a, b, m);
  if (s == Status::DegenerateResult) return flat_proximity(a, b, out);
  if (s != Status::Ok) return s;
  out = proximity(m, a, b);
  return Status::Ok;
}

namespace {

// The farthest pair of two boxes: the farthest vertex of M = c + G t. For a fixed corner t_A of
// A, |p + G_B t_B|^2 with p = c + G_A t_A separates into one term per axis of B (its axes are
// orthogonal), so the best t_B has the signs of g_Bj . p; compare the 8 corners of A by
// 2 t_A . (h_A u_A . c) + 2 sum_j |g_Bj . p|, the rest being the same for all.
void box_box_farthest(const detail::BoxPair<double>& p, Proximity& out) {
  double gbc[3], gab[3][3];
  for (int j = 0; j < 3; ++j) {
    gbc[j] = Vector3d(p.g[3 + j]).dot(Vector3d(p.c));
    for (int i = 0; i < 3; ++i) gab[i][j] = Vector3d(p.g[i]).dot(Vector3d(p.g[3 + j]));
  }
  double best = -std::numeric_limits<double>::infinity(), t[6] = {};
  for (int code = 0; code < 8; ++code) {
    const double s[3] = {code & 1 ? 1.0 : -1.0, code & 2 ? 1.0 : -1.0, code & 4 ? 1.0 : -1.0};
    double value = 0, tb[3];
    for (int j = 0; j < 3; ++j) {
      const double gp = gbc[j] + s[0] * gab[0][j] + s[1] * gab[1][j] + s[2] * gab[2][j];
      tb[j] = gp >= 0 ? 1 : -1;
      value += 2 * std::abs(gp) + 2 * s[j] * p.h[j] * p.uc[j];
    }
    if (value > best) best = value, t[0] = s[0], t[1] = s[1], t[2] = s[2], t[3] = tb[0], t[4] = tb[1], t[5] = tb[2];
  }
  Vector3d m(p.c), fa(p.ca);
  for (int k = 0; k < 6; ++k) {
    const Vector3d g(p.g[k]);
    m += t[k] * g;
    if (k < 3) fa += t[k] * g;
  }
  out.max_distance = m.norm(), out.far_a = fa, out.far_b = fa - m;
}

// The 15-facet evaluation of the batched kernel on one lane: the fallback if the active set
// does not settle.
Status box_box_exhaustive(const Box& a, const Box& b, Proximity& out) {
  BoxBatch<double, kLaneMultiple> A, B;
  BoxBoxProximity<double, kLaneMultiple> r;
  A.set(0, a), B.set(0, b);
  A.count = B.count = 1;
  A.pad(), B.pad();
  box_box_proximity(A, B, r);
  out.intersecting = !(r.distance[0] > 0);
  out.distance = r.distance[0];
  out.penetration_depth = r.depth[0];
  for (int d = 0; d < 3; ++d) {
    out.penetration_direction[d] = r.direction[d][0];
    out.point_a[d] = r.point_a[d][0], out.point_b[d] = r.point_b[d][0];
  }
  return Status::Ok;
}

}  // namespace

Status proximity(const Box& a, const Box& b, Proximity& out, Want want) {
  out = Proximity{};
  for (const Box* x : {&a, &b})
    if (const Status s = check_box(*x); s != Status::Ok) return s;
  detail::BoxPair<double> pair;
  detail::PairAnswer<double> r;
  detail::box_pair_proximity(a, b, want & kWantContact, pair, r);
  if (want & kWantContact) {
    if (!r.converged) {
      box_box_exhaustive(a, b, out);
    } else {
      out.intersecting = r.intersecting;
      out.distance = r.distance;
      out.penetration_depth = r.depth;
      out.penetration_direction = Vector3d(r.direction);
      out.point_a = Vector3d(r.point_a), out.point_b = Vector3d(r.point_b);
    }
  }
  if (want & kWantMaxDistance) box_box_farthest(pair, out);
  return Status::Ok;
}

Status proximity(const Box& a, const Triangle& b, Proximity& out) {
  ConvexPolytope pa, pb;
  Status s = polytope_from_box(a, pa);
  if (s == Status::Ok) s = polytope_from_triangle(b, pb);
  return s == Status::Ok ? proximity(pa, pb, out) : s;
}

Status proximity(const Triangle& a, const Triangle& b, Proximity& out) {
  ConvexPolytope pa, pb;
  Status s = polytope_from_triangle(a, pa);
  if (s == Status::Ok) s = polytope_from_triangle(b, pb);
  return s == Status::Ok ? proximity(pa, pb, out) : s;
}

}  // namespace minksum
