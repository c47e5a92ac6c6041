// The queries on two posed polytope cores (general, box, triangle), for the entry points that
// add the radii (rounded.cpp); internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// The exact proximity of two posed shapes whose cores have faces, without their radii:
/// boxes and triangles in their own form, else GJK under a certificate; through `cache` if
/// given. The shapes are not empty, the poses are checked and `out` is a default Proximity.
void core_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                    const Eigen::Isometry3d& pose_b, ProximityCache* cache, Proximity& out, Want want);

/// The contact patch of two such cores within `margin` (checked), without their radii.
Status core_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                  const Eigen::Isometry3d& pose_b, double margin, ProximityCache* cache, ContactPatch& out);

/// The contact patch of two posed cores (any: faceless ones too) within `margin`, from their
/// exact proximity `cores` (its witnesses, and its direction where they meet): the supporting
/// sets along its normal, seen along it, and their overlap.
Status answer_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                    const Eigen::Isometry3d& pose_b, const Proximity& cores, double margin, ContactPatch& out);

/// Clears the fields `want` does not ask for (the general path computes the first four levels
/// together: its certificate reads what the witnesses need).
inline void keep_asked(Want want, Proximity& out) {
  if (!has(want, Want::Witnesses)) out.point_a.setZero(), out.point_b.setZero();
  if (!has(want, Want::Distance)) out.distance = out.penetration_depth = 0, out.penetration_direction.setZero();
}

}  // namespace minksum::detail
