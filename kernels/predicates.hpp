// Sign-robust orientation predicate on double vectors (internal).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
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

/// The same sign as orient(p, c.q, c.r), reusing the cached cross product.
int orient(const Eigen::Vector3d& p, const Cross& c);

}  // namespace minksum::detail
