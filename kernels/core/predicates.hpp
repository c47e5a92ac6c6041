// Exact predicates on doubles (internal): a floating-point filter in front of exact expansions
// on the stack (expansion.hpp). No rational arithmetic, no allocation.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>
#include <vector>

namespace minksum::detail {

/// Components below this are flushed to zero in the Gauss normals (shape.cpp, overlay.cpp),
/// so that no product of three components underflows and the expansions stay exact.
constexpr double kTinyComponent = 0x1p-300;

/// How far a rounded Gauss normal's component (canonical: at most 1) may be from its exact
/// value: gauss_normal keeps a Newell normal in double only within this bound.
constexpr double kRoundedNormal = 1e-14;

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

/// The sign of det[p; q; r] where the doubles prove it though each component (at most 1) may
/// be off its exact value by kRoundedNormal (rounded Gauss normals, gauss_normal): at most 18
/// kRoundedNormal in all, on top of orient's own 7.8e-16 of the permanent; 0 where they cannot
/// (the exact vectors decide).
inline int orient_rounded_filter(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& r) {
  const Eigen::Vector3d c = q.cross(r);
  const double det = p.dot(c);
  const double perm = p.cwiseAbs().dot(Eigen::Vector3d(std::abs(q.y() * r.z()) + std::abs(q.z() * r.y()),
                                                       std::abs(q.z() * r.x()) + std::abs(q.x() * r.z()),
                                                       std::abs(q.x() * r.y()) + std::abs(q.y() * r.x())));
  return std::abs(det) > 1e-15 * perm + 20 * kRoundedNormal ? (det > 0 ? 1 : -1) : 0;
}

/// The exact sign of det[p; q; r] for exact vectors (every term 0 or within [2^-300, 2^300]).
int orient_exact(const ExactVector& p, const ExactVector& q, const ExactVector& r);

/// orient_exact's last stage alone, the expansions: for a caller whose filters (orient_near)
/// already failed.
int orient_expansions(const ExactVector& p, const ExactVector& q, const ExactVector& r);

/// An exact vector to about 106 bits: component k is hi[k] + lo[k] (|lo| <= ulp(hi) / 2), within
/// terms^2 2^-106 size of the exact one, size the largest sum of a component's terms' magnitudes
/// and terms the most terms of a component (near_vector).
struct NearVector {
  double hi[3], lo[3];
  double size;
  int terms;
};

/// x to about 106 bits (its terms summed by two-sum: Ogita, Rump and Oishi's Sum2, unrounded).
NearVector near_vector(const ExactVector& x);

/// Whether p x q != 0, where the vectors to 106 bits show it (false: they cannot tell; the
/// exact vectors decide, collinear_exact).
bool near_apart(const NearVector& p, const NearVector& q);

/// The sign of det[p; q; r] where the vectors to 106 bits decide it (a near-tie of rounded
/// normals, det ~ 1e-17, is decided here in about 400 instructions); 0 where they cannot (an
/// exact zero, or one within 2^-90 of the permanent: orient_exact decides).
int orient_near(const NearVector& p, const NearVector& q, const NearVector& r);

/// Whether the exact vectors p and q lie on one line (p x q = 0).
bool collinear_exact(const ExactVector& p, const ExactVector& q);

/// The Newell normal sum_k p_k x p_(k+1) of a closed loop, summed exactly and rounded once:
/// independent of the loop's start and of translation, and exactly negated for the negated,
/// reversed loop. `exact` (if given) tells whether the rounded vector is the exact one.
Eigen::Vector3d exact_newell(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop,
                             bool* exact = nullptr);

/// How a Gauss normal's exact value is had: it is the stored double vector (Exact), its
/// expansions are stored beside it (Stored), or they are computed from the face's loop when a
/// predicate first needs them (OnDemand: exact_gauss_normal).
enum class GaussKind : std::uint8_t { Exact, Stored, OnDemand };

/// A face's Gauss normal: canonical_direction of its loop's exact Newell normal. Exact where
/// that normal is a double vector or an axis. Else rounded: OnDemand where the Newell normal in
/// double proves every sign and lies within kRoundedNormal of the exact one scaled alike (the canonical
/// scale 2^-exponent, for exact_gauss_normal); else Stored, the exact normal's three
/// expansions scaled alike appended to `terms` (component k's count in count[k]; terms below
/// 2^-300 of the largest dropped). Exactly parallel faces get the same vector where the normal
/// is Exact.
Eigen::Vector3d gauss_normal(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& loop,
                             std::vector<double>& terms, int count[3], GaussKind& kind, int& exponent);

/// The exact normal of an OnDemand face (its loop of n vertex indices, the shape's vertices,
/// gauss_normal's exponent), in local[3 * kMaxGaussTerms].
ExactVector exact_gauss_normal(const int* loop, int n, const double* px, const double* py, const double* pz,
                               int exponent, double* local);

/// The exact normal of an OnDemand face (as exact_gauss_normal) to 106 bits, summed from its
/// Newell products in double-double, without expansions (terms: 4 per loop vertex, as many
/// as orient_near takes for up to 12; a loop of more, or a normal below 2^-200 of its
/// coordinates squared, gets more, which orient_near declines).
NearVector near_gauss_normal(const int* loop, int n, const double* px, const double* py, const double* pz,
                             int exponent);

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
