// Exact predicates on doubles (internal): a floating-point filter in front of exact expansions
// on the stack (expansion.hpp). No rational arithmetic, no allocation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <vector>

namespace minksum::detail {

/// Components below this are flushed to zero in the Gauss normals (shape.cpp, overlay.cpp),
/// so that no product of three components underflows and the expansions stay exact.
constexpr double kTinyComponent = 0x1p-300;

/// The exact sign of det[p; q; r], the side of the plane spanned by q and r on which p lies;
/// exact for the doubles as given when every component is 0 or within [2^-300, 2^300].
int orient_exact(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r);

/// The same sign, decided by a double evaluation whenever its error bound allows (Shewchuk's
/// static filter: the permanent bounds every rounding error), else by orient_exact.
inline int orient(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const double a = q.y() * r.z(), b = q.z() * r.y(), c = q.z() * r.x(), d = q.x() * r.z(), e = q.x() * r.y(),
               f = q.y() * r.x();
  const double det = p.x() * (a - b) + p.y() * (c - d) + p.z() * (e - f);
  const double perm = std::abs(p.x()) * (std::abs(a) + std::abs(b)) + std::abs(p.y()) * (std::abs(c) + std::abs(d)) +
                      std::abs(p.z()) * (std::abs(e) + std::abs(f));
  // Shewchuk's o3derrboundA is (7 + 56 eps) eps ~ 7.8e-16; 1e-15 is a safe round-up.
  if (std::abs(det) > 1e-15 * perm) return det > 0 ? 1 : -1;
  if (perm == 0) return 0;  // every product has a zero factor (none underflows in the callers' range)
  return orient_exact(p, q, r);
}

/// The Newell normal sum_k p_k x p_(k+1) of a closed loop, summed exactly and rounded once:
/// independent of the loop's start and of translation, and exactly negated for the negated,
/// reversed loop. `exact` (if given) tells whether the rounded vector is the exact one.
Eigen::Vector3d exact_newell(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop,
                             bool* exact = nullptr);

/// A loop's normal for a Gauss map, cheaply: the exact Newell normal (exact = true) when the
/// loop's coordinates are integers of at most 24 bits times a power of two; otherwise a vector
/// whose components have the exact one's signs, zeros included (exact = false): the Newell
/// normal in double where its error bounds prove them, else exact_newell's.
Eigen::Vector3d newell_normal(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop, bool& exact);

/// The cross product (q - p) x n, computed exactly and rounded once (a flat polygon's side
/// normal, outward for a counter-clockwise edge p -> q about n); `exact` as for exact_newell.
Eigen::Vector3d exact_edge_cross(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& n,
                                 bool* exact = nullptr);

/// The canonical representative of a direction for the exact predicates: an exact vector v
/// (exact = true) is divided by the greatest common divisor of its components (as integers
/// times a common power of two), so that parallel exact vectors become the same vector; every
/// vector is then scaled by a power of two to a largest component in [0.5, 1) and components
/// below kTinyComponent are flushed to zero. Zero stays zero.
Eigen::Vector3d canonical_direction(const Eigen::Vector3d& v, bool exact);

}  // namespace minksum::detail
