// The checks every entry point runs on its input (internal): coordinates, and the thresholds
// that make a point set flat or collinear.
#pragma once

#include <minksum/model.hpp>

#include <cstddef>

namespace minksum::detail {

/// Relative thresholds, in units of the input's bounding-box diagonal D. Points closer than
/// kFlatTol * D (64 eps: the queries' rounding tolerance) to a plane make the input flat; closer
/// than kLineTol * D to a line, collinear.
constexpr double kFlatTol = 64 * 0x1p-52;
constexpr double kLineTol = 1e-12;

/// NonFinite for a NaN or Inf coordinate, OutOfRange beyond kMaxCoordinate, else Ok.
Status check_coordinates(const Eigen::Vector3d* pts, size_t n);

/// The diagonal of the points' bounding box (n >= 1).
double diagonal(const Eigen::Vector3d* pts, size_t n);

/// True if the 3x3 matrix whose columns start at r, r + stride and r + 2 stride is a proper
/// rotation: orthonormal columns to 1e-9 and right-handed. NaN and Inf entries fail.
bool proper_rotation(const double* r, int stride);

}  // namespace minksum::detail
