// Sign-robust orientation predicate on double vectors (internal).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

namespace minksum::detail {

/// Exact sign of det[p; q; r] = p . (q x r) for the given doubles: -1, 0 or +1.
/// Filtered: a double evaluation with a forward error bound, exact rationals (GMP) only when
/// the double result is too close to zero to trust (Shewchuk-style static filter).
int orient(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r);

/// The Newell normal sum_k p_k x p_(k+1) of a closed loop, summed exactly and then rounded:
/// independent of the loop's start and of translation, and exactly negated for the negated,
/// reversed loop, so that parallel faces of A and -A get bitwise opposite normals.
Eigen::Vector3d exact_newell(const std::vector<Eigen::Vector3d>& points,
                             const std::vector<int>& loop);

/// q x r in double with the absolute values of its six products, for repeated orient calls.
struct Cross {
  Eigen::Vector3d q, r;    ///< the factors, kept for the exact fallback
  Eigen::Vector3d value;   ///< q x r rounded
  Eigen::Vector3d bound;   ///< per component |q_j r_k| + |q_k r_j|
};

/// Builds the cached cross product q x r.
Cross make_cross(const Eigen::Vector3d& q, const Eigen::Vector3d& r);

/// The exact sign of p . (q x r) in rational arithmetic (the filter's fallback).
int exact_orient(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r);

/// The same sign as orient(p, c.q, c.r), reusing the cached cross product. Inline: the
/// filter decides almost every call in a few multiply-adds.
inline int orient(const Eigen::Vector3d& p, const Cross& c) {
  const double det = p.dot(c.value);
  // The permanent bounds every rounding error of the six products and their sums.
  const double perm = p.cwiseAbs().dot(c.bound);
  // Shewchuk's o3derrboundA is (7 + 56 eps) eps ~ 7.8e-16; 1e-15 is a safe round-up.
  // Products that may have underflowed (perm < 1e-290) go to the exact path as well.
  if (std::abs(det) > 1e-15 * perm && perm > 1e-290) return det > 0 ? 1 : -1;
  if (perm == 0.0) return 0;  // every product is exactly zero
  // A repeated or exactly opposite row (antipodal normals are common: A and -A, symmetric
  // solids) makes the determinant exactly 0; the filter cannot see that.
  if (p == c.q || p == c.r || c.q == c.r || p == -c.q || p == -c.r || c.q == -c.r) return 0;
  return exact_orient(p, c.q, c.r);
}

}  // namespace minksum::detail
