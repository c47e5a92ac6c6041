// Rescaling by a power of two (internal): exact, and it keeps products in range.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>

namespace minksum::detail {

/// A power of two near 1 / size (2^-e where 2^(e-1) <= size < 2^e; 1 when size is not
/// positive): multiplying by it is exact and brings size into [0.5, 1), so that products of
/// a few scaled numbers neither overflow nor underflow. At most 2^1000, since the inverse of a
/// subnormal size would overflow; 2^1000 makes it normal.
inline double scale_to_one(double size) {
  int exponent = 0;
  std::frexp(size, &exponent);
  return size > 0 ? std::ldexp(1.0, std::min(-exponent, 1000)) : 1.0;
}

/// v / |v|, scaled first by a power of two, so that |v|^2 neither overflows (a Newell normal or
/// a cross product of edges at 1e100 is 1e200) nor underflows; a zero vector stays zero.
inline Eigen::Vector3d unit_vector(const Eigen::Vector3d& v) {
  const double m = v.cwiseAbs().maxCoeff();
  return m > 0 ? Eigen::Vector3d((v * scale_to_one(m)).normalized()) : v;
}

}  // namespace minksum::detail
