// An exact triangle-triangle distance (GMP rationals), the oracle of triangle_distance, the
// batched kernel and the octree.
#pragma once

#include <Eigen/Core>

namespace minksum::test {

/// The distance between two triangles (degenerate ones allowed), every step exact and one
/// rounding at the end; independent of the library's triangle_distance.
double exact_triangle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3]);

/// The same steps in double: fast, and rounded (every decision may err near a tie, and near-parallel
/// edges lose their interior pair): a first opinion that the exact one confirms where it matters.
double rounded_triangle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3]);

}  // namespace minksum::test
