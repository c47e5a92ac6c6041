// The advancement of time_of_impact (internal), shared by the convex pairs (impact.cpp) and
// a tool against a mesh's triangles (mesh/sweep.cpp).
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// A body moving within a tick: its vertices in its own frame and its motion from pose p0 to
/// p1, the origin along the segment and the rotation about one body axis at a constant rate.
struct Mover {
  const Eigen::Vector3d* vertices = nullptr;
  int size = 0;
  Eigen::Isometry3d p0 = Eigen::Isometry3d::Identity();
  Eigen::Vector3d v = Eigen::Vector3d::Zero();       ///< the origin's velocity, per tick
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();   ///< the rotation's body axis (unit)
  double angle = 0;                                  ///< and its angle per tick, in [0, pi]
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();   ///< the angular velocity, world frame (fixed)
  double radius = 0;                                 ///< the largest |x| of the vertices
  double across = 0;                                 ///< the largest distance of one from the axis
  const double *x = nullptr, *y = nullptr, *z = nullptr;  ///< the vertices as arrays, if any: a SIMD scan
  /// The body of `size` vertices moving from p0 to p1 (rigid poses, checked by the caller).
  Mover(const Eigen::Vector3d* vertices, int size, const Eigen::Isometry3d& p0, const Eigen::Isometry3d& p1);
  /// A prepared shape moving from p0 to p1, scanned from its vertex arrays.
  Mover(const ConvexShape& shape, const Eigen::Isometry3d& p0, const Eigen::Isometry3d& p1);
  /// Its pose at time t of the tick.
  Eigen::Isometry3d at(double t) const;
};

/// time_of_impact's default tolerance: 1e-12 of the scene's reach translating, 1e-6 turning.
inline double default_tolerance(const Mover& a, const Mover& b, double reach) {
  return (a.angle == 0 && b.angle == 0 ? 1e-12 : 1e-6) * reach;
}

/// What the advancement asks of a pair where GJK cannot go on (rounding, or an overlap).
class ExactAnswers {
 public:
  /// The exact query at the poses; false if there is none (the advancement stops there).
  virtual bool query(const Eigen::Isometry3d& pa, const Eigen::Isometry3d& pb, Proximity& out) const = 0;
  /// A certified normal (A towards B) of a contact within `margin` at the poses, near_a and
  /// near_b the advancement's nearest points there (a first candidate); false if none.
  virtual bool normal(const Eigen::Isometry3d& pa, const Eigen::Isometry3d& pb, double margin,
                      const Eigen::Vector3d& near_a, const Eigen::Vector3d& near_b, Eigen::Vector3d& out) const = 0;

 protected:
  ~ExactAnswers() = default;
};

/// The time of impact of B against A (see time_of_impact) within [0, limit]: past the limit,
/// no hit. `reach` bounds the scene's coordinates (the steps' scale and the start's slack).
/// Without an exact query where GJK stalls, it stops unconverged there. `radii`: the bodies are
/// cores swept by balls whose radii add up to it, so they hit where the cores come within
/// radii + tolerance (out's distance is the cores' less the radii; its points are the cores').
Status advance(const Mover& a, const Mover& b, double tolerance, double reach, double limit,
               const ExactAnswers& exact, double radii, TimeOfImpact& out);

}  // namespace minksum::detail
