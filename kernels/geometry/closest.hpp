// Closest points of primitives (internal): what the queries share with the triangle distance.
#pragma once

#include <Eigen/Core>

#include <algorithm>
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
  const Eigen::Vector3d q = lambda * u - r * n;  // (its projection onto the polygon's plane)
  for (int e = 0; e < k; ++e) {
    const Eigen::Vector3d a = corner(e), b = corner((e + 1) % k);
    if ((b - a).cross(q - a).dot(n) < 0) return none;
  }
  return lambda;
}

/// The exit of the ray lambda u from the rounded hull (conv p[0..n)) (+) B(r), n <= 8, from a
/// point inside it: every vertex's ball, every pair's cylinder and both sides of every triple's
/// slab (each lies in the rounded hull, and the hull's facets are triangulated by triples).
double rounded_hull_exit(const Eigen::Vector3d* p, int n, const Eigen::Vector3d& u, double r);

}  // namespace minksum::detail
