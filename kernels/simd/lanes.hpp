// The helpers every kernel family shares (internal): three-component lanes, dot and cross
// products, loads and stores of rows, parallel-edge guards and box supports, all templated on the
// float type T and the ISA. Each family (box_box.hpp, box_proximity.hpp, box_triangle.hpp,
// triangle_distance.hpp, support.hpp) derives from Lanes; kernel_bodies.hpp puts them in a table.
#pragma once

#include <array>
#include <limits>
#include <type_traits>
#include <utility>

#include "simd/simd.hpp"

namespace minksum::detail {

/// The lane helpers of one float type and ISA.
template <class T, class Arch>
struct Lanes {
  using S = Simd<T, Arch>;
  using B = typename S::B;

  struct V3 {
    B x, y, z;
  };
  static B dot(const V3& a, const V3& b) { return S::fma(a.x, b.x, S::fma(a.y, b.y, a.z * b.z)); }
  static V3 cross(const V3& a, const V3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
  /// a x b to a few ulps of each component, however nearly parallel a and b are (the plain
  /// product's error is an ulp of |a| |b|: for vectors sin t apart, 1 / sin t of the result's).
  static V3 cross_accurate(const V3& a, const V3& b) {
    const auto minor = [](const B& p, const B& q, const B& r, const B& s) { return minor_accurate<T, Arch>(p, q, r, s); };
    return {minor(a.y, b.z, a.z, b.y), minor(a.z, b.x, a.x, b.z), minor(a.x, b.y, a.y, b.x)};
  }
  static V3 scaled(const V3& a, const B& s) { return {a.x * s, a.y * s, a.z * s}; }
  static V3 load3(const T* p, int stride, int k) {
    return {S::load(p + k), S::load(p + stride + k), S::load(p + 2 * stride + k)};
  }
  static void store3(T* p, int stride, int k, const V3& v) {
    S::store(p + k, v.x);
    S::store(p + stride + k, v.y);
    S::store(p + 2 * stride + k, v.z);
  }
  // 1 / |c| for the cross product c of two edges, or 0 (and the valid bit clear) when
  // |c|^2 <= tau^2 * scale2: nearly parallel edges give no reliable direction. Nor does a
  // subnormal |c|^2 (edges under 1e-19 in float, where scale2 underflows to 0): its bits are
  // gone, and the hardware's rsqrt estimate reads it as 0 (inf, then NaN planes).
  static B inv_len_or_zero(const V3& c, const B& scale2, B& valid_bit, T bit) {
    const B len2 = dot(c, c);
    const B floor = S::max(B(kTau2) * scale2, B(std::numeric_limits<T>::min()));
    return inv_len_where(len2 > floor, len2, valid_bit, bit);
  }
  // The same from |c|^2, for the cross of two unit edge directions (scale 1).
  static B inv_len_or_zero(const B& len2, B& valid_bit, T bit) {
    return inv_len_where(len2 > B(kTau2), len2, valid_bit, bit);
  }
  static constexpr T kTau2 = kParallelThreshold<T> * kParallelThreshold<T>;
  template <class M>
  static B inv_len_where(const M& ok, const B& len2, B& valid_bit, T bit) {
    valid_bit = valid_bit + S::select(ok, B(bit), B(T(0)));
    return S::select(ok, S::rsqrt(S::select(ok, len2, B(T(1)))), B(T(0)));
  }
  // The unit axis of c, or the zero vector (see inv_len_or_zero).
  static V3 unit_or_zero(const V3& c, const B& scale2, B& valid_bit, T bit) {
    return scaled(c, inv_len_or_zero(c, scale2, valid_bit, bit));
  }
  // Support of a box in direction n: sum_k h_k |n . u_k|, and the corner code (bit k:
  // n . u_k > 0). All three terms are evaluated, even for an edge-cross axis that is
  // perpendicular to one box axis in exact arithmetic: the rounded normal is not, and its
  // small term keeps the offset exact to a few ulp for nearly parallel edges too.
  static void box_support(const V3& n, const V3 (&u)[3], const B (&h)[3], B& s, B& code) {
    s = B(T(0));
    code = B(T(0));
    for (int k = 0; k < 3; ++k) {
      const B d = dot(n, u[k]);
      s = S::fma(h[k], S::abs(d), s);
      code = S::select(d > B(T(0)), code + B(T(1 << k)), code);  // a masked add
    }
  }

  // Calls f(std::integral_constant<int, N>) for the row strides compiled fixed-size (powers of
  // two, 16 to 256), else f(std::integral_constant<int, 0>). A kernel that stores ~170 rows per
  // register spends about a quarter of its time forming row * N addresses when N is a runtime
  // value (they do not fit in registers); with N a constant they are immediate offsets.
  template <class F>
  static void with_row_stride(int N, F f) {
    switch (N) {
      case 16:
        return f(std::integral_constant<int, 16>{});
      case 32:
        return f(std::integral_constant<int, 32>{});
      case 64:
        return f(std::integral_constant<int, 64>{});
      case 128:
        return f(std::integral_constant<int, 128>{});
      case 256:
        return f(std::integral_constant<int, 256>{});
      default:
        return f(std::integral_constant<int, 0>{});
    }
  }

  static B pick(bool m, const B& a, const B& b) { return m ? a : b; }
  template <class M, class = std::enable_if_t<!std::is_same_v<M, bool>>>
  static B pick(const M& m, const B& a, const B& b) {
    return S::select(m, a, b);
  }
  static V3 axpy(const B& s, const V3& x, const V3& y) {
    return V3{S::fma(s, x.x, y.x), S::fma(s, x.y, y.y), S::fma(s, x.z, y.z)};
  }
  static V3 pick3(const decltype(B(T(0)) < B(T(0)))& m, const V3& a, const V3& b) {
    return {S::select(m, a.x, b.x), S::select(m, a.y, b.y), S::select(m, a.z, b.z)};
  }
  static B load_u(const T* p) {
    if constexpr (S::size == 1)
      return *p;
    else
      return B::load_unaligned(p);
  }
  static void store_u(T* p, const B& v) {
    if constexpr (S::size == 1)
      *p = v;
    else
      v.store_unaligned(p);
  }
};

}  // namespace minksum::detail
