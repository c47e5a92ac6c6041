// Closest points of primitives (internal): what the queries share with the triangle distance.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum::detail {

/// The parameter t in [0, 1] of the point a + t (b - a) nearest the origin; 0 when a = b.
inline double nearest_on_segment(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d e = b - a;
  const double len2 = e.squaredNorm();
  return len2 > 0 ? std::clamp(-a.dot(e) / len2, 0.0, 1.0) : 0.0;
}

/// Closest points cp on p0-p1 and cq on q0-q1 (Ericson, "Real-Time Collision Detection", 2005,
/// 5.1.9; the near-parallel terms by Lagrange's identity), degenerate segments included; their
/// squared distance. Products of four coordinates: the caller keeps them in range.
double segment_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1, Eigen::Vector3d& cp, Eigen::Vector3d& cq);

/// The point of the simplex w[0..n) (n <= 4) nearest the origin, as barycentric weights (zero
/// outside the nearest feature); false if the origin lies inside the tetrahedron.
bool nearest_on_simplex(const Eigen::Vector3d* w, int n, double (&lambda)[4]);

/// GJK's simplex on M = A (-) B (Gilbert, Johnson & Keerthi, IEEE J. Robotics and Automation
/// 4(2), 1988): up to four support pairs (a vertex of A, a vertex of B) and their points w of M,
/// as the proximity query's GJK (query/gjk.hpp) and the time of impact's advancement
/// (query/impact.cpp) both keep it.
struct PairSimplex {
  Eigen::Vector3d w[4];
  int ia[4] = {}, ib[4] = {};
  double l[4] = {};  // the weights of the nearest point, after reduce (0: not yet weighed)
  int n = 0;

  /// Whether the pair (ka, kb) is in it.
  bool holds(int ka, int kb) const {
    for (int j = 0; j < n; ++j)
      if (ia[j] == ka && ib[j] == kb) return true;
    return false;
  }
  /// Adds the pair (ka, kb) with its point of M (n < 4).
  void add(int ka, int kb, const Eigen::Vector3d& point) { w[n] = point, ia[n] = ka, ib[n] = kb, l[n] = 0, ++n; }
  /// Reduces it to the feature nearest the origin: keeps the pairs of positive weight (their
  /// weights in l, their old places in kept; the nearest point is the sum of l w). Returns how
  /// many are kept (0: no weight left, a NaN), or -1 where the origin lies inside the
  /// tetrahedron (it is left as it was).
  int reduce(int (&kept)[4]) {
    double lambda[4];
    if (!nearest_on_simplex(w, n, lambda)) return -1;
    int m = 0;
    for (int j = 0; j < n; ++j) {
      if (!(lambda[j] > 0)) continue;
      if (m < j) w[m] = w[j], ia[m] = ia[j], ib[m] = ib[j];  // (most steps keep every pair)
      l[m] = lambda[j], kept[m++] = j;
    }
    if (m > 0) n = m;
    return m;
  }
};

/// Where the ray lambda u (u unit) leaves the ball of radius r about c: the larger root, or -inf
/// where the ray's line misses the ball. The exits of a rounded polytope P (+) B(r), the union
/// of the balls about P's vertices, the cylinders about its edges and the slabs over its facets,
/// from a point inside: the largest exit of those pieces (the exit point's nearest point of P
/// lies on a vertex, an edge or a facet, whose piece it leaves there).
double ball_exit(const Eigen::Vector3d& c, const Eigen::Vector3d& u, double r);

/// Where the ray lambda u leaves the cylinder of radius r about the segment a b, if the axis
/// point there lies on the segment; else -inf.
double cylinder_exit(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& u, double r);

/// Where the ray lambda u leaves the slab n . x <= o + r (n unit, n . u > 0) over the convex
/// polygon of the k points corner(0..k) (counter-clockwise about n, in the plane n . x = o), if
/// the exit point projects onto the polygon; else -inf.
template <class Corner>
double slab_exit(Corner corner, int k, const Eigen::Vector3d& n, double o, const Eigen::Vector3d& u, double r) {
  const double along = n.dot(u), none = -std::numeric_limits<double>::infinity();
  if (!(along > 0)) return none;
  const double lambda = (o + r) / along;
  // A ray all but parallel to the slab (n . u denormal) leaves it at infinity, where q is NaN
  // (inf * 0): no exit. The side tests fail on NaN too (a fuzz finding: an infinite depth).
  if (!std::isfinite(lambda)) return none;
  const Eigen::Vector3d q = lambda * u - r * n;  // (its projection onto the polygon's plane)
  for (int e = 0; e < k; ++e) {
    const Eigen::Vector3d a = corner(e), b = corner((e + 1) % k);
    if (!((b - a).cross(q - a).dot(n) >= 0)) return none;
  }
  return lambda;
}

}  // namespace minksum::detail
