// The small overlay's sign tables, templated on the ISA (internal; see lanes.hpp and
// sum/overlay_small.cpp).
#pragma once

#include <cstdint>

#include "simd/lanes.hpp"

namespace minksum::detail {

/// Sides of many normals against up to 64 arcs' poles, as bit masks.
template <class Arch>
struct SideKernels : Lanes<double, Arch> {
  using L = Lanes<double, Arch>;
  using L::load_u;
  using typename L::S, typename L::B;

  // For each vector g_j (j < m): bit i of out[j] set iff p_i . g_j > filter (i < n <= 64; the
  // columns px, py, pz hold n rounded up to 8 entries). False at the first j where some
  // |p_i . g_j| <= filter: a sign the doubles do not decide (out is then partly written).
  static bool side_masks(const double* px, const double* py, const double* pz, int n, const double* gx,
                         const double* gy, const double* gz, int m, double filter, std::uint64_t* out) {
    const std::uint64_t used = n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1;
    const B f(filter), minus_f(-filter);
    for (int j = 0; j < m; ++j) {
      const B x(gx[j]), y(gy[j]), z(gz[j]);
      std::uint64_t left = 0, right = 0;
      for (int i = 0; i < n; i += S::size) {
        const B v = S::fma(x, load_u(px + i), S::fma(y, load_u(py + i), z * load_u(pz + i)));
        left |= std::uint64_t(S::bits(v > f)) << i;
        right |= std::uint64_t(S::bits(v < minus_f)) << i;
      }
      if (~(left | right) & used) return false;  // some |v| <= filter
      out[j] = left & used;
    }
    return true;
  }
};

}  // namespace minksum::detail
