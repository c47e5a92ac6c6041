// Point and segment cores (a sphere's centre, a capsule's segment) against any core: the
// queries of the shapes without faces, for the posed entry points (rounded.cpp); internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

/// A point or segment core placed in some frame: its ends (equal for a point).
struct Segment {
  Eigen::Vector3d s0, s1;
};

/// The closest points of a and b (geometry's segment_segment, relative to a's first end and
/// scaled by a power of two so that its products stay in range); their distance.
double closest_segments(const Segment& a, const Segment& b, Eigen::Vector3d& pa, Eigen::Vector3d& pb);

/// The proximity of two point or segment cores, before the radii: their nearest points; where
/// they meet, depth 0 (their difference has no interior) and a direction across both.
void segment_pair(const Segment& a, const Segment& b, Proximity& out);

/// The proximity of a point or segment core A (world frame) and a polytope core B (general, box
/// or triangle) placed by pose_b, before the radii: the exact distance and its nearest points,
/// or, meeting, the depth, its direction (B moves along it) and the deepest points. `face`
/// carries the face of B that held the last separated answer from call to call (-1: none,
/// cold): where the nearest points on it are still proven nearest by the planes through them,
/// the query reads that face alone. Returns whether the answer came from it.
bool segment_polytope(const Segment& a, const ConvexShape& b, const Eigen::Isometry3d& pose_b, int& face,
                      Proximity& out);

}  // namespace minksum::detail
