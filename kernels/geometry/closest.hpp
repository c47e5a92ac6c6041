// Closest points of primitives (internal): what the queries share with the triangle distance.
#pragma once

#include <Eigen/Core>

#include <algorithm>

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

}  // namespace minksum::detail
