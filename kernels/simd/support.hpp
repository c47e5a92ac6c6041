// The support-push kernel, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"

namespace minksum::detail {

/// Support pushes: the highest vertex per direction.
template <class T, class Arch>
struct SupportKernels : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::load_u;
  using typename L::S, typename L::B, typename L::V3;

  // Support push: per direction, max of d . v over vertices and the first index attaining it.
  static void support(const T* x, const T* y, const T* z, int n, const T* dx, const T* dy, const T* dz, int K,
                      T* max_out, int* arg_out) {
    const int full = n - n % S::size;
    alignas(64) T lane_idx[S::size];
    for (int l = 0; l < S::size; ++l) lane_idx[l] = T(l);
    const B iota = S::load(lane_idx);
    for (int q = 0; q < K; ++q) {
      const B bx(dx[q]), by(dy[q]), bz(dz[q]);
      B best(-std::numeric_limits<T>::infinity()), arg(0);
      for (int k = 0; k < full; k += S::size) {
        // Unaligned callers are allowed here: the vertex arrays are the caller's own.
        const B d = S::fma(bx, load_u(x + k), S::fma(by, load_u(y + k), bz * load_u(z + k)));
        const auto better = d > best;
        best = S::select(better, d, best);
        arg = S::select(better, iota + B(T(k)), arg);
      }
      alignas(64) T b[S::size], a[S::size];
      S::store(b, best);
      S::store(a, arg);
      T top = -std::numeric_limits<T>::infinity();
      int at = 0;
      for (int l = 0; l < S::size; ++l)  // lanes in index order keep the first maximiser
        if (b[l] > top || (b[l] == top && int(a[l]) < at)) top = b[l], at = int(a[l]);
      for (int k = full; k < n; ++k) {
        const T d = dx[q] * x[k] + (dy[q] * y[k] + dz[q] * z[k]);
        if (d > top) top = d, at = k;
      }
      max_out[q] = top;
      arg_out[q] = at;
    }
  }
};

}  // namespace minksum::detail
