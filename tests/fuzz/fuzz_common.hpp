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

inline bool finite(const Eigen::Vector3d& v) { return std::isfinite(v.x()) && std::isfinite(v.y()) && std::isfinite(v.z()); }

}  // namespace minksum::fuzz
