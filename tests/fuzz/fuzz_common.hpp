// Shared by the libFuzzer targets: reads doubles and floats off the fuzzer's bytes (raw bit
// patterns, so NaN, Inf, subnormals and huge values all occur) and the checks every target
// makes on a result.
#pragma once

#include <minksum/minksum.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <cstdio>

namespace minksum::fuzz {

/// Consumes the input front to back; past the end it yields zeros.
struct Bytes {
  const uint8_t* p;
  size_t n;
  template <class T>
  T take() {
    T v{};
    const size_t k = n < sizeof(T) ? n : sizeof(T);
    std::memcpy(&v, p, k);
    p += k, n -= k;
    return v;
  }
  /// A double that is usually a small plain number and sometimes any bit pattern.
  double number() {
    const uint8_t mode = take<uint8_t>();
    if (mode < 200) return double(take<int16_t>()) / 64.0;  // lattice: duplicates, coplanarity
    return take<double>();
  }
};

/// Aborts (a finding) with a message.
[[noreturn]] inline void fail(const char* what) {
  std::fprintf(stderr, "fuzz check failed: %s\n", what);
  std::abort();
}

inline bool finite(const Eigen::Vector3d& v) {
  return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z());
}

/// The checks on any proximity answer: finite, consistent (distance >= 0, witnesses that
/// realise it, intersecting at distance 0). `reach`: the largest coordinate of the operands,
/// where the caller knows it (max_distance bounds it only when the query was asked for it,
/// Want::MaxDistance).
inline void check(const Proximity& p, double reach = 0) {
  for (double x : {p.distance, p.max_distance, p.penetration_depth})
    if (!std::isfinite(x) || x < 0) fail("distance, max distance or depth not finite and >= 0");
  for (const auto* v : {&p.point_a, &p.point_b, &p.far_a, &p.far_b, &p.penetration_direction})
    if (!finite(*v)) fail("non-finite point or direction");
  if (p.intersecting && p.distance != 0) fail("intersecting with a positive distance");
  // Rounding is relative to the largest coordinate involved (the farthest pair bounds it).
  const double scale =
      1 + reach + p.max_distance + p.point_a.cwiseAbs().maxCoeff() + p.point_b.cwiseAbs().maxCoeff();
  if (!p.intersecting && std::abs((p.point_a - p.point_b).norm() - p.distance) > 1e-6 * scale)
    fail("the closest points do not realise the distance");
}

}  // namespace minksum::fuzz
