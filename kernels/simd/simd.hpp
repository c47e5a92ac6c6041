// A thin layer over xsimd so that one kernel body serves every ISA and the scalar path
// (internal; included only by the per-ISA translation units).
#pragma once

#include <minksum/kernels.hpp>
#include <xsimd/xsimd.hpp>

#include <cmath>
#include <limits>
#include <type_traits>

namespace minksum::detail {

/// Tag of the plain C++ path (one lane, no intrinsics).
struct ScalarArch {};

/// The error a b - p of p = fl(a b) (lanes V of T), by Dekker's split ("A floating-point
/// technique for extending the available precision", 1971): exact without overflow, for |a|,
/// |b| below 2^115 in float and 2^996 in double. Arch keeps each ISA translation unit's copy
/// its own (see BoxPairQuery).
template <class T, class Arch, class V>
V dekker_error(const V& a, const V& b, const V& p) {
  const V f(T(std::is_same_v<T, float> ? 4097 : 134217729));  // 2^12 + 1, 2^27 + 1
  const V ca = f * a, cb = f * b;
  const V ah = ca - (ca - a), bh = cb - (cb - b);
  const V al = a - ah, bl = b - bh;
  return ((ah * bh - p) + ah * bl + al * bh) + al * bl;
}

/// p + e == a b exactly, p = fl(a b), for lanes V of T or one T: by a fused multiply-add
/// where Arch has one, else by Dekker's split (xsimd's fma is unfused on SSE). Same bits on
/// every ISA.
template <class T, class Arch, class V>
void two_product(const V& a, const V& b, V& p, V& e) {
  p = a * b;
  if constexpr (std::is_base_of_v<xsimd::avx512f, Arch> || std::is_base_of_v<xsimd::fma3<xsimd::avx2>, Arch>) {
    if constexpr (std::is_same_v<V, T>)
      e = std::fma(a, b, -p);  // (a hardware instruction in these translation units)
    else
      e = xsimd::fma(a, b, V(T(0)) - p);
  } else {
    e = dekker_error<T, Arch>(a, b, p);
  }
}

/// p q - r s to a few ulps, however much the products cancel (x - y is exact where they do:
/// Sterbenz); the plain difference errs by an ulp of |p q|.
template <class T, class Arch, class V>
V minor_accurate(const V& p, const V& q, const V& r, const V& s) {
  V x, ex, y, ey;
  two_product<T, Arch>(p, q, x, ex), two_product<T, Arch>(r, s, y, ey);
  return (x - y) + (ex - ey);
}

/// Lanes of T on Arch, with the handful of operations the kernels use.
template <class T, class Arch>
struct Simd {
  using B = xsimd::batch<T, Arch>;
  static constexpr int size = int(B::size);
  static B load(const T* p) { return B::load_aligned(p); }
  static void store(T* p, const B& v) { v.store_aligned(p); }
  static B fma(const B& a, const B& b, const B& c) { return xsimd::fma(a, b, c); }
  static B abs(const B& a) { return xsimd::abs(a); }
  static B sqrt(const B& a) { return xsimd::sqrt(a); }
  static B max(const B& a, const B& b) { return xsimd::max(a, b); }
  static B min(const B& a, const B& b) { return xsimd::min(a, b); }
  /// 1 / sqrt(x) to the precision of T, for x in [1e-30, 1e30]. In double, a square root and a
  /// division: they run in the divider, beside the multiply pipes the kernels fill, where an
  /// estimate's refinement takes six to ten more multiplies (measured: the batched box-box
  /// distance 8 % faster on AVX2 and SSE4.2, the same on AVX-512). In float the wider lanes make
  /// the divider the bottleneck: a hardware estimate refined by Newton steps
  /// y <- y (3/2 - x y^2 / 2), each of which doubles the correct bits. (Not xsimd::rsqrt: on
  /// AVX-512 it emits AVX-512ER instructions that only Xeon Phi has.)
  static B rsqrt(const B& x) {
    if constexpr (std::is_same_v<T, double>) {
      return B(T(1)) / xsimd::sqrt(x);
    } else {
      // A 14-bit (AVX-512) or 12-bit estimate: one Newton step reaches float's 24 bits.
      B y;
      if constexpr (std::is_same_v<Arch, xsimd::avx512bw>)
        y = B(_mm512_rsqrt14_ps(x));
      else
        y = xsimd::rsqrt(x);
      return y * (B(T(1.5)) - x * B(T(0.5)) * y * y);
    }
  }
  template <class M>
  static B select(const M& m, const B& a, const B& b) {
    return xsimd::select(m, a, b);
  }
  template <class M>
  static bool any(const M& m) {
    return xsimd::any(m);
  }
  /// Stores integers held exactly in T (|v| < 2^51) as integer codes. Below AVX-512 there is no
  /// packed double -> int64 conversion, and xsimd converts lane by lane through memory (measured:
  /// 44 % of the double box-box sum kernel on AVX2). Instead, v + 1.5 * 2^52 is exact and holds
  /// v in its low mantissa bits, two's complement: its bits minus those of 1.5 * 2^52 are v.
  static void store_code(CodeOf<T>* p, const B& v) {
    if constexpr (std::is_same_v<T, double> && !std::is_same_v<Arch, xsimd::avx512bw>) {
      using I = xsimd::batch<std::int64_t, Arch>;
      const I bits = xsimd::bitwise_cast<I>(v + B(0x1.8p52));
      (bits - I(std::int64_t(0x4338000000000000))).store_aligned(p);
    } else {
      xsimd::batch_cast<CodeOf<T>>(v).store_aligned(p);
    }
  }
  /// The lanes of a mask (of T, or of 64-bit integers) as bits, lane l in bit l (xsimd 8 has
  /// no such call).
  template <class M>
  static unsigned bits(const M& m) {
    constexpr bool wide = sizeof(m.data) == 32, of_t = std::is_same_v<M, typename B::batch_bool_type>;
    if constexpr (std::is_same_v<Arch, xsimd::avx512bw>)
      return unsigned(m.data);
    else if constexpr (!of_t && wide)
      return unsigned(_mm256_movemask_pd(_mm256_castsi256_pd(m.data)));
    else if constexpr (!of_t)
      return unsigned(_mm_movemask_pd(_mm_castsi128_pd(m.data)));
    else if constexpr (wide && std::is_same_v<T, float>)
      return unsigned(_mm256_movemask_ps(m));
    else if constexpr (wide)
      return unsigned(_mm256_movemask_pd(m));
    else if constexpr (std::is_same_v<T, float>)
      return unsigned(_mm_movemask_ps(m));
    else
      return unsigned(_mm_movemask_pd(m));
  }
};

template <class T>
struct Simd<T, ScalarArch> {
  using B = T;
  static constexpr int size = 1;
  static B load(const T* p) { return *p; }
  static void store(T* p, B v) { *p = v; }
  // Not std::fma: without FMA hardware flags it is a slow library call; the scalar path is the
  // portable baseline and rounds twice, like SSE.
  static B fma(B a, B b, B c) { return a * b + c; }
  static B abs(B a) { return std::abs(a); }
  static B sqrt(B a) { return std::sqrt(a); }
  static B max(B a, B b) { return a > b ? a : b; }
  static B min(B a, B b) { return a < b ? a : b; }
  static B rsqrt(B x) { return T(1) / std::sqrt(x); }
  static B select(bool m, B a, B b) { return m ? a : b; }
  static bool any(bool m) { return m; }
  static void store_code(CodeOf<T>* p, B v) { *p = CodeOf<T>(v); }
  static unsigned bits(bool m) { return m; }
};

template <class T>
struct BoxPair;
template <class T>
struct PairAnswer;
enum class PairLevel : int;

/// The kernels of one ISA, as plain function pointers (one table per ISA translation unit).
struct KernelTable {
  void (*box_box_f)(BoxLanes<float>, BoxLanes<float>, int, int, bool, PlaneLanes<float>, SumLanes<float>);
  void (*box_box_d)(BoxLanes<double>, BoxLanes<double>, int, int, bool, PlaneLanes<double>, SumLanes<double>);
  void (*box_tri_f)(BoxLanes<float>, const float*, int, int, bool, PlaneLanes<float>);
  void (*box_tri_d)(BoxLanes<double>, const double*, int, int, bool, PlaneLanes<double>);
  void (*support_f)(const float*, const float*, const float*, int, const float*, const float*, const float*, int,
                    float*, int*);
  void (*support_d)(const double*, const double*, const double*, int, const double*, const double*, const double*, int,
                    double*, int*);
  void (*box_box_single_d)(const double*, bool, double*, double*, std::int64_t*, std::int64_t*);
  void (*box_box_proximity_f)(BoxLanes<float>, BoxLanes<float>, int, int, ProximityLanes<float>);
  void (*box_box_proximity_d)(BoxLanes<double>, BoxLanes<double>, int, int, ProximityLanes<double>);
  void (*box_box_separation_f)(BoxLanes<float>, BoxLanes<float>, int, int, float*, std::int32_t*);
  void (*box_box_separation_d)(BoxLanes<double>, BoxLanes<double>, int, int, double*, std::int64_t*);
  void (*box_triangle_overlap_f)(BoxLanes<float>, const float*, int, int, std::int32_t*);
  void (*box_triangle_overlap_d)(BoxLanes<double>, const double*, int, int, std::int64_t*);
  void (*box_pair_d)(const BoxLanes<double>&, const BoxLanes<double>&, PairLevel, unsigned&, BoxPair<double>&,
                     PairAnswer<double>&);
  void (*tri_tri_f)(const float*, const float*, int, int, float*, float*, float*);
  void (*tri_tri_d)(const double*, const double*, int, int, double*, double*, double*);
  bool (*side_masks_d)(const double*, const double*, const double*, int, const double*, const double*, const double*,
                       int, double, std::uint64_t*);
};

// One constant-initialised table per ISA translation unit (no static-initialisation order
// problem: they exist before any code runs).
extern const KernelTable kTableScalar, kTableSse4_2, kTableAvx2, kTableAvx512;

}  // namespace minksum::detail
