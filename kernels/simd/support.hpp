// The support-push kernel, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"

namespace minksum::detail {

/// Support pushes: the highest vertex per direction.
template <class T, class Arch>
struct SupportKernels : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::load_u, L::store_u;
  using typename L::S, typename L::B, typename L::V3;

  // Support push: per direction, max of d . v over vertices and the first index attaining it.
  // Whole blocks of S::size directions run across the lanes, a vertex per step: no reduction
  // across lanes, and no scalar tail however few the vertices (a 16-lane register holds more
  // lanes than an 8-vertex shape has vertices). The directions left over run one at a time,
  // across the vertices.
  static void support(const T* x, const T* y, const T* z, int n, const T* dx, const T* dy, const T* dz, int K,
                      T* max_out, int* arg_out) {
    // (One lane: the loop over the vertices, which GCC compiles 2x faster there at 64 of them.)
    const int blocks = S::size == 1 ? 0 : K - K % S::size;
    for (int q = 0; q < blocks; q += S::size) {
      const B bx = load_u(dx + q), by = load_u(dy + q), bz = load_u(dz + q);
      B best(-std::numeric_limits<T>::infinity()), arg(T(0));
      for (int k = 0; k < n; ++k) {  // strictly greater: the first maximiser stays
        const B d = S::fma(bx, B(x[k]), S::fma(by, B(y[k]), bz * B(z[k])));
        const auto better = d > best;
        best = S::select(better, d, best);
        arg = S::select(better, B(T(k)), arg);
      }
      alignas(64) T a[S::size];
      S::store(a, arg);
      store_u(max_out + q, best);
      for (int l = 0; l < S::size; ++l) arg_out[q + l] = int(a[l]);
    }
    for (int q = blocks; q < K; ++q) one_direction(x, y, z, n, dx[q], dy[q], dz[q], max_out[q], arg_out[q]);
  }

  // One direction across the vertices, S::size at a time, then the lanes in index order.
  static void one_direction(const T* x, const T* y, const T* z, int n, T dx, T dy, T dz, T& top, int& at) {
    const int full = n - n % S::size;
    alignas(64) T lane_idx[S::size];
    for (int l = 0; l < S::size; ++l) lane_idx[l] = T(l);
    const B iota = S::load(lane_idx), bx(dx), by(dy), bz(dz);
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
    top = -std::numeric_limits<T>::infinity(), at = 0;
    for (int l = 0; l < S::size; ++l)  // lanes in index order keep the first maximiser
      if (b[l] > top || (b[l] == top && int(a[l]) < at)) top = b[l], at = int(a[l]);
    for (int k = full; k < n; ++k) {
      const T d = dx * x[k] + (dy * y[k] + dz * z[k]);
      if (d > top) top = d, at = k;
    }
  }
};

}  // namespace minksum::detail
