// What the time of impact asks of rounded shapes (rounded.cpp); internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// The exact proximity of the cores of two posed shapes, their radii left out (valid shapes,
/// checked poses): a GJK-stalled advancement's exact query on the cores.
void cores_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, Proximity& out);

/// The contact patch of the cores of two posed shapes within `margin`, their radii left out.
Status cores_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                   const Eigen::Isometry3d& pose_b, double margin, ContactPatch& out);

}  // namespace minksum::detail
