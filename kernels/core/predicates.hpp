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

/// The most terms a Gauss normal's component keeps (gauss_normal; a loop's Newell normal needs
/// 2 to 4 on coordinates of one scale).
constexpr int kMaxGaussTerms = 8;

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

/// A vector given exactly: each component an expansion (expansion.hpp) of `count[k]` terms
/// (0: zero), times `sign` (+1 or -1). A Gauss normal of rounded coordinates is one.
struct ExactVector {
  const double* terms[3];
  int count[3];
  double sign;
};

/// The exact vector equal to the doubles v (which must outlive it).
inline ExactVector exact_vector(const Eigen::Vector3d& v) {
  return {{&v.x(), &v.y(), &v.z()}, {v.x() != 0, v.y() != 0, v.z() != 0}, 1.0};
}

/// The sign of det[p; q; r] where the doubles prove it though each component may be off its
/// exact value by 2^-52 of itself (rounded Gauss normals: 3 x 2^-52 of each product, on top
/// of orient's own 7.8e-16); 0 where they cannot (the exact vectors decide).
inline int orient_rounded_filter(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const Eigen::Vector3d c = q.cross(r);
  const double det = p.dot(c);
  const double perm = p.cwiseAbs().dot(Eigen::Vector3d(std::abs(q.y() * r.z()) + std::abs(q.z() * r.y()),
                                                       std::abs(q.z() * r.x()) + std::abs(q.x() * r.z()),
                                                       std::abs(q.x() * r.y()) + std::abs(q.y() * r.x())));
  return std::abs(det) > 2e-15 * perm ? (det > 0 ? 1 : -1) : 0;
}

/// The exact sign of det[p; q; r] for exact vectors (every term 0 or within [2^-300, 2^300]).
int orient_exact(const ExactVector& p, const ExactVector& q, const ExactVector& r);

/// Whether the exact vectors p and q point exactly the same way (p x q = 0, p . q > 0).
bool same_direction_exact(const ExactVector& p, const ExactVector& q);

/// The Newell normal sum_k p_k x p_(k+1) of a closed loop, summed exactly and rounded once:
/// independent of the loop's start and of translation, and exactly negated for the negated,
/// reversed loop. `exact` (if given) tells whether the rounded vector is the exact one.
Eigen::Vector3d exact_newell(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop,
                             bool* exact = nullptr);

/// A face's Gauss normal: canonical_direction of its loop's exact Newell normal. Where that
/// normal is not a double vector (rounded coordinates), its three expansions, scaled by the
/// power of two that made it canonical, are appended to `terms` (component k's count in
/// count[k]; terms below 2^-300 of the largest dropped) and `exact` is false; else nothing is
/// appended (counts 0) and `exact` is true. Exactly parallel faces get the same vector where
/// the normal is exact, or where one loop is the other scaled by a power of two.
Eigen::Vector3d gauss_normal(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop,
                             std::vector<double>& terms, int count[3], bool& exact);

/// A flat polygon's side normal: canonical_direction of (q - p) x n, exactly (n the
/// polygon's exact normal; an outward side normal for a counter-clockwise edge p -> q about
/// n); terms and `exact` as for gauss_normal.
Eigen::Vector3d gauss_side_normal(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const ExactVector& n,
                                  std::vector<double>& terms, int count[3], bool& exact);

/// The canonical representative of a direction for the exact predicates: an exact vector v
/// (exact = true) is divided by the greatest common divisor of its components (as integers
/// times a common power of two), so that parallel exact vectors become the same vector; every
/// vector is then scaled by a power of two to a largest component in [0.5, 1) and components
/// below kTinyComponent are flushed to zero. Zero stays zero.
Eigen::Vector3d canonical_direction(const Eigen::Vector3d& v, bool exact);

}  // namespace minksum::detail
