// The kernel bodies, templated on the float type T and the ISA (internal). Each per-ISA
// translation unit includes this file with its own compiler flags and instantiates
// make_table<Arch>(); the bodies use only the Simd<T, Arch> operations.
#pragma once

#include <array>
#include <limits>
#include <type_traits>
#include <utility>

#include "simd/box_pair.hpp"
#include "simd/simd.hpp"

namespace minksum::detail {

template <class T, class Arch>
struct Kernels {
  using S = Simd<T, Arch>;
  using B = typename S::B;

  struct V3 {
    B x, y, z;
  };
  static B dot(const V3& a, const V3& b) { return S::fma(a.x, b.x, S::fma(a.y, b.y, a.z * b.z)); }
  static V3 cross(const V3& a, const V3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
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
  // |c|^2 <= tau^2 * scale2: nearly parallel edges give no reliable direction.
  static B inv_len_or_zero(const V3& c, const B& scale2, B& valid_bit, T bit) {
    const B len2 = dot(c, c);
    return inv_len_where(len2 > B(kTau2) * scale2, len2, valid_bit, bit);
  }
  // The same from |c|^2, for the cross of two unit edge directions (scale 1).
  static B inv_len_or_zero(const B& len2, B& valid_bit, T bit) {
    return inv_len_where(len2 > B(kTau2), len2, valid_bit, bit);
  }
  static constexpr T kTau2 = kParallelThreshold<T> * kParallelThreshold<T>;
  template <class M>
  static B inv_len_where(const M& ok, const B& len2, B& valid_bit, T bit) {
    valid_bit = valid_bit + S::select(ok, B(bit), B(T(0)));
    // In double, a square root and a division: they run in the divider, beside the multiply
    // pipes the kernels fill, where the estimate's refinement (S::rsqrt) takes six more
    // multiplies (measured: the box-box kernel 3% faster on Zen 5). In float the wider lanes
    // make the divider the bottleneck.
    const B x = S::select(ok, len2, B(T(1)));
    return S::select(ok, std::is_same_v<T, double> ? B(T(1)) / S::sqrt(x) : S::rsqrt(x), B(T(0)));
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
      case 16: return f(std::integral_constant<int, 16>{});
      case 32: return f(std::integral_constant<int, 32>{});
      case 64: return f(std::integral_constant<int, 64>{});
      case 128: return f(std::integral_constant<int, 128>{});
      case 256: return f(std::integral_constant<int, 256>{});
      default: return f(std::integral_constant<int, 0>{});
    }
  }

  // Box-box: 15 axes, 30 planes (see BoxBoxPlanes), worked in A's frame, where A's axes are
  // e_0, e_1, e_2 and B's are the columns of C = U_A^T U_B (the OBB separating-axis formulation
  // of Gottschalk, Lin and Manocha, "OBBTree", SIGGRAPH 1996). The edge axis e_i x C_j then has
  // two nonzero components, -C[i2][j] and C[i1][j] (i1, i2 = i + 1, i + 2 mod 3), and every dot
  // product the plane needs is formed from those same two numbers: the normal and its offset
  // stay consistent (no rounding error divided by |u_i x v_j| for nearly parallel edges), and all
  // of it is linear in the unnormalised axis, so the dot products run while 1/|axis| is
  // computed. The normal is taken back to the world frame as U_A times the A-frame axis.
  static void box_box(BoxLanes<T> a, BoxLanes<T> b, int count, int N, bool difference,
                      PlaneLanes<T> out, SumLanes<T> sum) {
    with_row_stride(N, [&](auto R) { box_box_rows<R.value>(a, b, count, N, difference, out, sum); });
  }
  // R: the row stride N fixed at compile time, or 0 (any N).
  template <int R>
  static void box_box_rows(BoxLanes<T> a, BoxLanes<T> b, int count, int any_N, bool difference,
                           PlaneLanes<T> out, SumLanes<T> sum) {
    const int N = R ? R : any_N;
    const B sign(difference ? T(-1) : T(1)), zero(0), one(1);
    const bool whole = sum.loop && !difference;  // the whole polytope too (sums only)
    auto bit = [&](const auto& m, int k) { return S::select(m, B(T(1 << k)), zero); };
    for (int k = 0; k < count; k += S::size) {
      // The inputs are read where they are used, not held: the body needs more registers than
      // there are, and an input held across it is spilled, a store more beside the ~170 rows
      // it writes per lane block (fewer spills measured faster). The outputs may alias the
      // inputs as far as the compiler knows, so these are real loads, and loads are cheap.
      const auto ua = [&](int i) { return load3(a.u + 3 * i * N, N, k); };
      const auto ub = [&](int j) { return load3(b.u + 3 * j * N, N, k); };
      const auto ha = [&](int i) { return S::load(a.h + i * N + k); };
      const auto hb = [&](int j) { return S::load(b.h + j * N + k); };
      B C[3][3], A[3][3];
      {
        const V3 u[3] = {ua(0), ua(1), ua(2)}, v[3] = {ub(0), ub(1), ub(2)};
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j) C[i][j] = dot(u[i], v[j]), A[i][j] = S::abs(C[i][j]);
      }
      // General position: no C entry near 0 (three coplanar edges). Formed here while A is live,
      // in every mode (nine min operations), rather than held for the end of a whole sum.
      B least = A[0][0];
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) least = S::min(least, A[i][j]);
      // The sum's reference point: c_A + c_B (or c_A - c_B for the difference), and in A's frame.
      const V3 ca = load3(a.c, N, k), cb = load3(b.c, N, k);
      const V3 c{S::fma(sign, cb.x, ca.x), S::fma(sign, cb.y, ca.y), S::fma(sign, cb.z, ca.z)};
      const B cA[3] = {dot(ua(0), c), dot(ua(1), c), dot(ua(2), c)};
      B valid(T(63));  // the six face axes are always valid
      // Writes axis p: normal n, support radius s about c, n . c, corner codes (B's already
      // shifted to bits 3-5). For the difference, B's support in n is its corner opposite to the
      // one in +n: 7 - code.
      auto emit = [&](int p, const V3& n, const B& s, const B& m, const B& codea, const B& codeb8) {
        const B code = codea + (difference ? B(T(56)) - codeb8 : codeb8);
        if (whole) sum_loops(p, code, sum.loop + k, N);
        store3(out.n + 3 * p * N, N, k, n);
        S::store(out.offset + p * N + k, s + m);
        S::store(out.offset + (p + 15) * N + k, s - m);
        S::store_code(out.code + p * N + k, code);
      };
#pragma GCC unroll 3
      for (int p = 0; p < 3; ++p) {
        emit(p, ua(p), ha(p) + S::fma(hb(0), A[p][0], S::fma(hb(1), A[p][1], hb(2) * A[p][2])), cA[p],
             B(T(1 << p)), bit(C[p][0] > zero, 3) + bit(C[p][1] > zero, 4) + bit(C[p][2] > zero, 5));
        const V3 v = ub(p);
        emit(3 + p, v, hb(p) + S::fma(ha(0), A[0][p], S::fma(ha(1), A[1][p], ha(2) * A[2][p])),
             dot(v, c), bit(C[0][p] > zero, 0) + bit(C[1][p] > zero, 1) + bit(C[2][p] > zero, 2),
             B(T(8 << p)));
      }
#pragma GCC unroll 3
      for (int i = 0; i < 3; ++i) {
        const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
        // x[j] = (e_i x C_j) . C_j1, a 2x2 minor of C. The axis (i, j) needs v . C_k for B's
        // other two axes (its own is 0): v . C_j1 = x[j] and v . C_j2 = -x[j2], so each minor
        // serves two axes and is formed once.
        B x[3], ax[3];
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j) {
          const int j1 = (j + 1) % 3;
          x[j] = S::fma(B(T(0)) - C[i2][j], C[i1][j1], C[i1][j] * C[i2][j1]);
          ax[j] = S::abs(x[j]);
        }
#pragma GCC unroll 3
        for (int j = 0; j < 3; ++j) {
          const int p = 6 + 3 * i + j, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
          // v = e_i x C_j: v_i = 0, v_i1 = -C[i2][j], v_i2 = C[i1][j].
          const B v1 = B(T(0)) - C[i2][j], v2 = C[i1][j];
          const B inv = inv_len_or_zero(S::fma(v1, v1, v2 * v2), valid, T(1 << p));
          const B s = S::fma(ha(i1), A[i2][j], S::fma(ha(i2), A[i1][j], S::fma(hb(j1), ax[j], hb(j2) * ax[j2])));
          const B w1 = v1 * inv, w2 = v2 * inv;
          const V3 u1 = ua(i1), u2 = ua(i2);
          const V3 n{S::fma(w1, u1.x, w2 * u2.x), S::fma(w1, u1.y, w2 * u2.y), S::fma(w1, u1.z, w2 * u2.z)};
          // Corner codes from the signs (all clear for an invalid axis, as its zero normal).
          emit(p, n, s * inv, S::fma(w1, cA[i1], w2 * cA[i2]), bit(w1 > zero, i1) + bit(w2 > zero, i2),
               S::select(inv > zero, bit(x[j] > zero, 3 + j1) + bit(x[j2] < zero, 3 + j2), zero));
        }
      }
      S::store_code(out.valid + k, valid);
      if (whole) {
        const auto general = valid == B(T((1 << 15) - 1)) && least > B(kParallelThreshold<T>);
        S::store_code(sum.general + k, S::select(general, one, zero));
        const V3 u[3] = {ua(0), ua(1), ua(2)}, v[3] = {ub(0), ub(1), ub(2)};
        const B g[3] = {ha(0), ha(1), ha(2)}, h[3] = {hb(0), hb(1), hb(2)};
        box_corners(load3(a.c, N, k), u, g, sum.corner_a + k, N);
        box_corners(load3(b.c, N, k), v, h, sum.corner_b + k, N);
      }
    }
  }

  // The vertex loops of the parallelogram facets q and q + 15 of a box-box sum in general
  // position, from the + plane's support pair v0 = code_a | code_b << 3 (tie bits clear): facet
  // p moves from its first vertex v0 along the facet's two edges, e then f, with e x f along the
  // outward normal; the opposite facet p + 15 starts at the complemented corners and goes f then
  // e. A loop packs four 6-bit vertex codes a | b << 3 (a 24-bit integer: exact in float).
  static void sum_loops(int q, const B& v0, CodeOf<T>* loop, int N) {
    const T K = T(1 + 64 + 4096 + 262144);  // v0 in all four slots
    const auto pack = [](int e, int f) { return T(e * 64 + (e + f) * 4096 + f * 262144); };
    // The facet's edges as code increments: A's axis bits count 1, 2, 4, B's 8, 16, 32.
    int e, f;
    if (q < 6) {
      const int base = q < 3 ? 1 : 8, axis = q % 3;
      e = base << ((axis + 1) % 3), f = base << ((axis + 2) % 3);
    } else {
      e = 1 << ((q - 6) / 3), f = 8 << ((q - 6) % 3);
    }
    // v0 of the + facet: the support corners with the edges' bits clear (a face axis's own bit
    // is set on the + side); of the - facet: the complement, the edges' bits clear too.
    const B v0K = v0 * B(K);  // (63 - e - f - v0) K + pack(f, e) for the - facet
    S::store_code(loop + q * N, v0K + B(pack(e, f)));
    S::store_code(loop + (q + 15) * N, B(T(63 - e - f) * K + pack(f, e)) - v0K);
  }

  // The eight corners c + sum_a (+-h_a) u_a of a box, corner i with bit a set on the + side:
  // the three half-edge vectors once, then sums.
  static void box_corners(const V3& c, const V3 (&u)[3], const B (&h)[3], T* corner, int N) {
    const V3 g[3] = {scaled(u[0], h[0]), scaled(u[1], h[1]), scaled(u[2], h[2])};
    // Level by level, each into a new array (GCC 12 -O3 miscompiled an in-place version for
    // scalar floats).
    const auto step = [&](const V3& x, int a, bool plus) {
      return plus ? V3{x.x + g[a].x, x.y + g[a].y, x.z + g[a].z}
                  : V3{x.x - g[a].x, x.y - g[a].y, x.z - g[a].z};
    };
    const V3 x[2] = {step(c, 0, false), step(c, 0, true)};
    V3 y[4];
    for (int i = 0; i < 4; ++i) y[i] = step(x[i & 1], 1, i & 2);
    for (int i = 0; i < 8; ++i) store3(corner + 3 * i * N, N, 0, step(y[i & 3], 2, i & 4));
  }

  // One box pair with its 15 axes in the lanes (16 with a padding lane): the single-pair API,
  // built from the same helpers as box_box. in = c_A, c_B (3 each), the axes u_A0..2, u_B0..2
  // (3 each), h_A, h_B (3 each). Out, per axis lane q: n[d * 16 + q], off[q] (plane +n),
  // off[16 + q] (plane -n), code[q] as in BoxBoxPlanes, valid[q] in {0, 1}.
  static void box_box_axes(const T* in, bool difference, T* n, T* off, CodeOf<T>* code,
                           CodeOf<T>* valid) {
    const T* u = in + 6;  // axis k of the six at u[3k..3k+2]
    // Per lane: the face axis itself (kFace), or the two edge directions whose cross is the axis
    // (kE of A, kF of B); kFixA/kFixB: the codes a face axis fixes (own bit set, the rest are
    // ties, left clear; -1: computed). Lane 15 pads.
    static constexpr int kFace[16] = {0, 1, 2, 3, 4, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    static constexpr int kE[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 0};
    static constexpr int kF[16] = {4, 4, 4, 4, 4, 4, 3, 4, 5, 3, 4, 5, 3, 4, 5, 4};
    alignas(64) static constexpr T kIsFace[16] = {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    alignas(64) static constexpr T kFixA[16] = {1, 2, 4, -1, -1, -1, -1, -1,
                                                -1, -1, -1, -1, -1, -1, -1, -1};
    alignas(64) static constexpr T kFixB[16] = {-1, -1, -1, 1, 2, 4, -1, -1,
                                                -1, -1, -1, -1, -1, -1, -1, -1};
    alignas(64) T face[3][16], e[3][16], f[3][16];
#pragma GCC unroll 16
    for (int q = 0; q < 16; ++q)
      for (int d = 0; d < 3; ++d) {
        face[d][q] = u[3 * kFace[q] + d];
        e[d][q] = u[3 * kE[q] + d];
        f[d][q] = u[3 * kF[q] + d];
      }
    auto broadcast = [](const T* p) { return V3{B(p[0]), B(p[1]), B(p[2])}; };
    const V3 ua[3] = {broadcast(u), broadcast(u + 3), broadcast(u + 6)};
    const V3 ub[3] = {broadcast(u + 9), broadcast(u + 12), broadcast(u + 15)};
    const B ha[3] = {B(in[24]), B(in[25]), B(in[26])}, hb[3] = {B(in[27]), B(in[28]), B(in[29])};
    const T s = difference ? T(-1) : T(1);
    const V3 c{B(in[0] + s * in[3]), B(in[1] + s * in[4]), B(in[2] + s * in[5])};
    const B flip(s), bias(difference ? T(7) : T(0)), zero(T(0)), one(T(1));
    // Unrolled, so that the register batches' dependency chains (cross, rsqrt, dots) overlap.
#pragma GCC unroll 16
    for (int q = 0; q < 16; q += S::size) {
      const auto face_lane = S::load(kIsFace + q) > zero;
      // v is the face axis or the (unnormalised) edge cross; everything below is linear in v,
      // so the dot products run while 1/|v| is still being computed, and are scaled after.
      const V3 x = cross(load3(&e[0][0], 16, q), load3(&f[0][0], 16, q));
      const V3 fc = load3(&face[0][0], 16, q);
      const V3 v{S::select(face_lane, fc.x, x.x), S::select(face_lane, fc.y, x.y),
                 S::select(face_lane, fc.z, x.z)};
      B ok(T(0));
      const B inv = S::select(face_lane, one, inv_len_or_zero(x, one, ok, T(1)));
      B sa, codea, sb, codeb;
      box_support(v, ua, ha, sa, codea);
      box_support(v, ub, hb, sb, codeb);
      const V3 nq = scaled(v, inv);
      sa = sa * inv, sb = sb * inv;
      const B fa = S::load(kFixA + q), fb = S::load(kFixB + q);
      codea = S::select(fa >= zero, fa, codea);
      codeb = S::select(fb >= zero, fb, codeb);
      const B r = sa + sb, m = dot(v, c) * inv;
      store3(n, 16, q, nq);
      S::store(off + q, r + m);
      S::store(off + 16 + q, r - m);
      S::store_code(code + q, S::fma(S::fma(codeb, flip, bias), B(T(8)), codea));
      S::store_code(valid + q, S::select(face_lane, one, ok));
    }
  }

  // Box-box proximity on the zonotope M = A (-) B = c + sum_k t_k g_k, t in [-1, 1]^6, with
  // c = c_A - c_B and generators g = (h_Ak u_Ak, -h_Bk u_Bk). Each pair (i, j) of generators
  // spans the facets +-(g_i x g_j); a facet is F0 + a g_i + b g_j (a, b in [-1, 1]) with the
  // other generators at the sign that is extreme along the normal. Separated (some axis has a
  // positive separation): the distance is the smallest distance from the origin to the facets
  // on its side, each one a 2D box-constrained least-squares problem (the unconstrained optimum, else the optimum on an
  // edge whose line separates it from the square, which the affine map keeps). Overlapping:
  // the separating axis theorem's smallest overlap over the 15 axes is the exact depth.
  // Exactly parallel generators span no facet, and the facets of the other pairs then cover
  // the merged ones between them; nearly parallel ones (below kSliverThreshold) span slivers
  // that are skipped, which moves the distance by at most that fraction of a half extent.
  // Most lanes need one facet: the fast path (proximity_fast) solves only the separating axis
  // test's choice and keeps it where a certificate proves it; the rest take all 15.

  using Mask = decltype(B(T(0)) < B(T(0)));
  // The facet's generator pair (I, J), known at compile time (one pair per lane group).
  template <int I, int J>
  struct FixedPair {
    static constexpr bool is_i(int q) { return q == I; }
    static constexpr bool is_j(int q) { return q == J; }
    static constexpr bool skip(int q) { return q == I || q == J; }  // statically one of the pair
  };
  // A pair per lane (the fast path's chosen facet): is_i(q), is_j(q) are lane masks.
  struct LanePair {
    Mask i[6], j[6];
    const Mask& is_i(int q) const { return i[q]; }
    const Mask& is_j(int q) const { return j[q]; }
    static constexpr bool skip(int) { return false; }
  };
  static B pick(bool m, const B& a, const B& b) { return m ? a : b; }
  template <class M, class = std::enable_if_t<!std::is_same_v<M, bool>>>
  static B pick(const M& m, const B& a, const B& b) { return S::select(m, a, b); }
  static V3 axpy(const B& s, const V3& x, const V3& y) {
    return V3{S::fma(s, x.x, y.x), S::fma(s, x.y, y.y), S::fma(s, x.z, y.z)};
  }
  static V3 pick3(const decltype(B(T(0)) < B(T(0)))& m, const V3& a, const V3& b) {
    return {S::select(m, a.x, b.x), S::select(m, a.y, b.y), S::select(m, a.z, b.z)};
  }

  // One facet pair (g_i, g_j) of the zonotope, evaluated for the origin.
  struct FacetEval {
    B dist2;    // squared distance from the origin to the facet (this pair's part), inf if invalid
    B overlap;  // SAT overlap along the axis (inf if the axis is invalid)
    B err;      // how far the facet's closest point is from the origin's projection
    B tol;      // tie tolerance of the overlap
    V3 n_out;   // the facet's unit outward normal on the origin's side
    V3 pa, P;   // closest point of the facet (P, a point of M) and its preimage on A
  };

  template <class Role>
  [[gnu::always_inline]] static FacetEval facet(const Role& role, const V3& c, const V3& ca, const V3 (&g)[6],
                         const B (&g2)[6], const V3& gi, const V3& gj) {
    const B zero(T(0)), one(T(1)), inf(std::numeric_limits<T>::infinity());
    auto sgn = [&](const B& v) { return S::select(v < zero, -one, one); };
    auto clamp1 = [&](const B& v) { return S::max(-one, S::select(v > one, one, v)); };
    const V3 x = cross(gi, gj);
    const B x2 = dot(x, x);
    const B sliver2(kSliverThreshold<T> * kSliverThreshold<T>);
    const auto valid = (x2 > sliver2 * dot(gi, gi) * dot(gj, gj));
    B dots[6], r = zero;
    for (int q = 0; q < 6; ++q) dots[q] = dot(x, g[q]), r = r + S::abs(dots[q]);
    const B s = dot(x, c), abs_s = S::abs(s);
    const B inv = S::select(valid, S::rsqrt(S::select(valid, x2, one)), zero);
    const B sigma = S::select(s < zero, one, -one);  // the facet on the origin's side
    FacetEval f;
    f.overlap = S::select(valid, (r - abs_s) * inv, inf);
    f.tol = B(T(64) * std::numeric_limits<T>::epsilon()) * r * inv;
    f.n_out = scaled(x, sigma * inv);
    // F0: the other generators at their extreme sign along sigma x. A generator in the facet's
    // plane (parallel to g_i or g_j, or to both: |x . g_q| below the sliver threshold) has no
    // extreme sign; the facet is then a zonogon, covered by the pairs that include the parallel
    // generators only if each takes the sign towards the origin's projection (then, along each
    // parallel family, the pairs' ranges overlap over the target side).
    B extreme[6];
    decltype(zero < zero) inplane[6];
    bool any_inplane = false;  // rare (parallel boxes): the second pass only runs then
    V3 F0 = c;
    for (int q = 0; q < 6; ++q) {
      extreme[q] = sgn(sigma * dots[q]);
      if (role.skip(q)) continue;
      const B own = pick(role.is_i(q), zero, pick(role.is_j(q), zero, one));  // 0: i or j
      inplane[q] = (dots[q] * dots[q] <= sliver2 * x2 * g2[q]) && (own > zero);
      any_inplane = any_inplane || S::any(inplane[q]);
      F0 = axpy(S::select(inplane[q], zero, own * extreme[q]), g[q], F0);
    }
    for (int q = 0; q < 6 && any_inplane; ++q) {
      if (role.skip(q)) continue;
      extreme[q] = S::select(inplane[q], zero - sgn(dot(g[q], F0)), extreme[q]);
      F0 = axpy(S::select(inplane[q], extreme[q], zero), g[q], F0);
    }
    // The 2D least-squares problem over (a, b) in [-1, 1]^2.
    const B G11 = dot(gi, gi), G22 = dot(gj, gj), G12 = dot(gi, gj);
    const B r1 = dot(gi, F0), r2 = dot(gj, F0);
    const B det = S::select(valid, x2, one);  // = G11 G22 - G12^2, without its cancellation
    const B as = (G12 * r2 - G22 * r1) / det, bs = (G12 * r1 - G11 * r2) / det;
    const auto a_out = S::abs(as) > one, b_out = S::abs(bs) > one;
    // Candidate on a = +-1 (if a* is beyond it) and on b = +-1 (if b* is).
    const B a1 = clamp1(as), b1 = clamp1(S::select(a_out, (zero - (r2 + a1 * G12)) / G22, bs));
    const B b2 = clamp1(bs), a2 = clamp1(S::select(b_out, (zero - (r1 + b2 * G12)) / G11, as));
    const V3 p1 = axpy(b1, gj, axpy(a1, gi, F0)), p2 = axpy(b2, gj, axpy(a2, gi, F0));
    const B d1 = dot(p1, p1), d2 = S::select(b_out, dot(p2, p2), inf);
    const auto second = d2 < d1;
    const B ab = S::select(second, a2, a1), bb = S::select(second, b2, b1);
    f.P = pick3(second, p2, p1);
    f.dist2 = S::select(valid, S::select(second, d2, d1), inf);
    // The point on A: c_A plus A's generators at their parameters.
    f.pa = ca;
    for (int q = 0; q < 3; ++q)
      f.pa = axpy(pick(role.is_i(q), ab, pick(role.is_j(q), bb, extreme[q])), g[q], f.pa);
    const V3 miss = axpy(-f.overlap, f.n_out, f.P);
    f.err = S::select(valid, dot(miss, miss), inf);
    return f;
  }

  // Running choice over facets: the nearest separating facet, and the deepest axis. Equal depths
  // (parallel generators give several pairs per facet, each covering part of it) go to the pair
  // whose part holds the origin's projection: those are the deepest points.
  struct Fold {
    B best2, depth, deep_err, least;  // least: the smallest overlap (< 0: separated)
    V3 best_pa, best_p, dir, deep_pa, deep_p;
    Fold() {
      const B inf(std::numeric_limits<T>::infinity()), zero(T(0));
      best2 = depth = deep_err = least = inf;
      best_pa = best_p = dir = deep_pa = deep_p = V3{zero, zero, zero};
    }
    void add(const FacetEval& f) {
      const auto deeper = (f.overlap < depth - f.tol) || ((f.overlap <= depth + f.tol) && (f.err < deep_err));
      depth = S::select(deeper, f.overlap, depth);
      deep_err = S::select(deeper, f.err, deep_err);
      dir = pick3(deeper, f.n_out, dir), deep_pa = pick3(deeper, f.pa, deep_pa);
      deep_p = pick3(deeper, f.P, deep_p);
      least = S::min(least, f.overlap);
      const auto better = f.dist2 < best2;
      best2 = S::select(better, f.dist2, best2);
      best_pa = pick3(better, f.pa, best_pa), best_p = pick3(better, f.P, best_p);
    }
  };

  static void generators(const V3 (&ua)[3], const B (&ha)[3], const V3 (&ub)[3], const B (&hb)[3],
                         V3 (&g)[6]) {
    for (int i = 0; i < 3; ++i) g[i] = scaled(ua[i], ha[i]), g[3 + i] = scaled(ub[i], B(T(0)) - hb[i]);
  }

  template <int P>
  static void fold_pair(Fold& fold, const V3& c, const V3& ca, const V3 (&g)[6], const B (&g2)[6]) {
    // The 15 generator pairs: (0,1) (0,2) (1,2) (3,4) (3,5) (4,5), then (A_i, B_j).
    constexpr int kI[15] = {0, 0, 1, 3, 3, 4, 0, 0, 0, 1, 1, 1, 2, 2, 2};
    constexpr int kJ[15] = {1, 2, 2, 4, 5, 5, 3, 4, 5, 3, 4, 5, 3, 4, 5};
    fold.add(facet(FixedPair<kI[P], kJ[P]>{}, c, ca, g, g2, g[kI[P]], g[kJ[P]]));
  }
  template <int... P>
  static void fold_all(Fold& fold, const V3& c, const V3& ca, const V3 (&g)[6], const B (&g2)[6],
                       std::integer_sequence<int, P...>) {
    (fold_pair<P>(fold, c, ca, g, g2), ...);
  }

  // Loads one register of box pairs: unit axes, half extents, A's centre, c = c_A - c_B, the
  // generators and their squared lengths.
  struct PairRegister {
    V3 ua[3], ub[3], g[6], ca, c;
    B ha[3], hb[3], g2[6];
    PairRegister(BoxLanes<T> a, BoxLanes<T> b, int N, int k) {
      for (int i = 0; i < 3; ++i) {
        ua[i] = load3(a.u + 3 * i * N, N, k), ub[i] = load3(b.u + 3 * i * N, N, k);
        ha[i] = S::load(a.h + i * N + k), hb[i] = S::load(b.h + i * N + k);
      }
      generators(ua, ha, ub, hb, g);
      ca = load3(a.c, N, k);
      const V3 cb = load3(b.c, N, k);
      c = V3{ca.x - cb.x, ca.y - cb.y, ca.z - cb.z};
      for (int q = 0; q < 6; ++q) g2[q] = dot(g[q], g[q]);
    }
  };

  static void store_proximity(ProximityLanes<T> out, int N, int k, const B& separated,
                              const B& distance, const B& depth, const V3& dir, const V3& pa,
                              const V3& p) {
    S::store(out.distance + k, distance);
    S::store(out.depth + k, depth);
    store3(out.direction, N, k, scaled(dir, B(T(1)) - separated));
    store3(out.point_a, N, k, pa);
    store3(out.point_b, N, k, V3{pa.x - p.x, pa.y - p.y, pa.z - p.z});
  }

  // All 15 facet pairs of one register of lanes (k .. k + S::size).
  static void proximity_all_facets(BoxLanes<T> a, BoxLanes<T> b, int N, int k,
                                   ProximityLanes<T> out) {
    const B zero(T(0)), one(T(1));
    const PairRegister r(a, b, N, k);
    Fold fold;
    fold_all(fold, r.c, r.ca, r.g, r.g2, std::make_integer_sequence<int, 15>{});
    // Separated or not is one decision, the separating axis test's: judging each facet's plane
    // on its own let rounding call one part of a facet split between parallel generator pairs
    // separating and another not, and the distance came from the wrong part (320.9 for
    // touching boxes in float). Every facet part is in M, so when separated the
    // nearest of all of them is the nearest point of M.
    const auto separated = fold.least < zero;
    store_proximity(out, N, k, S::select(separated, one, zero),
                    S::select(separated, S::sqrt(fold.best2), zero),
                    S::select(separated, zero, fold.depth), fold.dir,
                    pick3(separated, fold.best_pa, fold.deep_pa), pick3(separated, fold.best_p, fold.deep_p));
  }

  // The fast path for one register: the separating axis test picks each lane's facet (the axis
  // of largest separation, or of smallest overlap), that one facet is solved, and the answer is
  // kept where it proves itself: separated, the plane through the closest point P normal to P
  // supports M (min over M of P . y = P . c - sum |P . g_q| >= |P|^2, up to rounding); overlapping,
  // the origin's projection onto the facet's plane lies in the facet. Elsewhere (the closest
  // point on another facet, a facet split between parallel generator pairs) the distance is
  // written as NaN for the caller to redo the lane over all facets.
  static void proximity_fast(BoxLanes<T> a, BoxLanes<T> b, int N, int k, ProximityLanes<T> out) {
    constexpr int kI[15] = {0, 0, 1, 3, 3, 4, 0, 0, 0, 1, 1, 1, 2, 2, 2};
    constexpr int kJ[15] = {1, 2, 2, 4, 5, 5, 3, 4, 5, 3, 4, 5, 3, 4, 5};
    const B zero(T(0)), one(T(1)), inf(std::numeric_limits<T>::infinity());
    const PairRegister r(a, b, N, k);
    // The separation of each axis from C = U_A^T U_B and c in A's frame (OBBTree's form, as
    // in box_box_separation but with the C shortcuts: it only chooses the facet).
    B C[3][3], absC[3][3], cA[3], cB[3];
    for (int i = 0; i < 3; ++i) {
      cA[i] = dot(r.ua[i], r.c), cB[i] = dot(r.ub[i], r.c);
      for (int j = 0; j < 3; ++j) C[i][j] = dot(r.ua[i], r.ub[j]), absC[i][j] = S::abs(C[i][j]);
    }
    B best(-inf), best_i(zero), best_j(zero);  // the best axis and its generator pair
    const auto keep = [&](const B& sep, int p) {
      const auto better = sep > best;
      best = S::select(better, sep, best);
      best_i = S::select(better, B(T(kI[p])), best_i), best_j = S::select(better, B(T(kJ[p])), best_j);
    };
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {  // face axis i of A is spanned by pair 2 - i, of B by 5 - i
      keep(S::abs(cA[i]) - (r.ha[i] + S::fma(r.hb[0], absC[i][0], S::fma(r.hb[1], absC[i][1], r.hb[2] * absC[i][2]))), 2 - i);
      keep(S::abs(cB[i]) - (r.hb[i] + S::fma(r.ha[0], absC[0][i], S::fma(r.ha[1], absC[1][i], r.ha[2] * absC[2][i]))), 5 - i);
    }
    const B sliver2(kSliverThreshold<T> * kSliverThreshold<T>);
#pragma GCC unroll 3
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3;
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        const int j1 = (j + 1) % 3, j2 = (j + 2) % 3;
        // L = u_Ai x u_Bj: |L|^2 = C_i1j^2 + C_i2j^2, L . c = cA_i1 C_i2j - cA_i2 C_i1j, and
        // the radius from the rows and columns of |C| (right-handed frames).
        const B len2 = S::fma(C[i1][j], C[i1][j], C[i2][j] * C[i2][j]);
        const B rad = S::fma(r.ha[i1], absC[i2][j], S::fma(r.ha[i2], absC[i1][j],
                             S::fma(r.hb[j1], absC[i][j2], r.hb[j2] * absC[i][j1])));
        const B lc = cA[i1] * C[i2][j] - cA[i2] * C[i1][j];
        const auto ok = len2 > sliver2;
        keep(S::select(ok, (S::abs(lc) - rad) * S::rsqrt(S::select(ok, len2, one)), -inf), 6 + 3 * i + j);
      }
    }
    LanePair role;
    V3 gi{zero, zero, zero}, gj = gi;
#pragma GCC unroll 6
    for (int q = 0; q < 6; ++q) {
      role.i[q] = best_i == B(T(q)), role.j[q] = best_j == B(T(q));
      gi = pick3(role.i[q], r.g[q], gi), gj = pick3(role.j[q], r.g[q], gj);
    }
    const FacetEval f = facet(role, r.c, r.ca, r.g, r.g2, gi, gj);
    // Rounding scale of the certificates: the sizes of c and of the generators (|g_q|_1 <=
    // sqrt(3) h_q).
    B scale = S::abs(r.c.x) + S::abs(r.c.y) + S::abs(r.c.z);
    for (int q = 0; q < 3; ++q) scale = S::fma(B(T(2)), r.ha[q] + r.hb[q], scale);
    const B tol = B(T(64) * std::numeric_limits<T>::epsilon()) * scale;
    B low = dot(f.P, r.c);  // min over M of P . y; |P|^2 = dist2 on a separated lane
    for (int q = 0; q < 6; ++q) low = low - S::abs(dot(f.P, r.g[q]));
    const auto separated = best > zero && f.dist2 < inf;
    const B dist = S::sqrt(S::select(separated, f.dist2, zero));
    const auto proven = (separated && low >= f.dist2 - dist * tol) ||
                        (best <= zero && f.overlap < inf && f.err <= tol * tol);
    const B nan(std::numeric_limits<T>::quiet_NaN());
    store_proximity(out, N, k, S::select(separated, one, zero), S::select(proven, dist, nan),
                    S::select(separated, zero, f.overlap), f.n_out, f.pa, f.P);
  }

  // One pair per lane: the fast path, then the lanes it could not prove through all facets,
  // gathered S::size at a time into local lanes.
  static void box_box_proximity(BoxLanes<T> a, BoxLanes<T> b, int count, int N,
                                ProximityLanes<T> out) {
    for (int k = 0; k < count; k += S::size) proximity_fast(a, b, N, k, out);
    constexpr int L = S::size;
    alignas(64) T in[2][15 * L], res[11 * L];
    int lane[L], n = 0;
    const auto redo = [&] {
      for (int m = n; m < L; ++m) lane[m] = lane[0];  // pad with copies of a redone lane
      for (int s = 0; s < 2; ++s) {
        const BoxLanes<T>& box = s ? b : a;
        for (int m = 0; m < L; ++m)
          for (int d = 0; d < 3; ++d) {
            in[s][d * L + m] = box.c[d * N + lane[m]];
            in[s][(12 + d) * L + m] = box.h[d * N + lane[m]];
            for (int e = 0; e < 3; ++e) in[s][(3 + 3 * e + d) * L + m] = box.u[(3 * e + d) * N + lane[m]];
          }
      }
      const BoxLanes<T> la{in[0], in[0] + 3 * L, in[0] + 12 * L}, lb{in[1], in[1] + 3 * L, in[1] + 12 * L};
      proximity_all_facets(la, lb, L, 0, {res, res + L, res + 2 * L, res + 5 * L, res + 8 * L});
      for (int m = 0; m < n; ++m) {
        out.distance[lane[m]] = res[m], out.depth[lane[m]] = res[L + m];
        for (int d = 0; d < 3; ++d) {
          out.direction[d * N + lane[m]] = res[(2 + d) * L + m];
          out.point_a[d * N + lane[m]] = res[(5 + d) * L + m];
          out.point_b[d * N + lane[m]] = res[(8 + d) * L + m];
        }
      }
      n = 0;
    };
    for (int k = 0; k < count; ++k)
      if (!(out.distance[k] == out.distance[k]) && (lane[n++] = k, n == L)) redo();
    if (n > 0) redo();
  }

  // The separating axis test fused into one pass, no planes written: is the origin inside
  // A (-) B, and a lower bound of the distance (the largest separation over the 15 axes), for
  // octree traversal and broad phases. Edge axes use the unnormalised cross product and scale
  // the separation once.
  static void box_box_separation(BoxLanes<T> a, BoxLanes<T> b, int count, int N, T* bound,
                                 CodeOf<T>* hit) {
    const B zero(T(0)), one(T(1));
    for (int k = 0; k < count; k += S::size) {
      V3 ua[3], ub[3];
      B ha[3], hb[3];
      for (int i = 0; i < 3; ++i) {
        ua[i] = load3(a.u + 3 * i * N, N, k), ub[i] = load3(b.u + 3 * i * N, N, k);
        ha[i] = S::load(a.h + i * N + k), hb[i] = S::load(b.h + i * N + k);
      }
      const V3 ca = load3(a.c, N, k), cb = load3(b.c, N, k);
      const V3 c{ca.x - cb.x, ca.y - cb.y, ca.z - cb.z};
      B sep(-std::numeric_limits<T>::infinity());
      auto radius = [&](const V3& n) {
        B r(T(0));
        for (int q = 0; q < 3; ++q)
          r = S::fma(ha[q], S::abs(dot(n, ua[q])), S::fma(hb[q], S::abs(dot(n, ub[q])), r));
        return r;
      };
      for (int p = 0; p < 3; ++p) {
        sep = S::max(sep, S::abs(dot(ua[p], c)) - radius(ua[p]));
        sep = S::max(sep, S::abs(dot(ub[p], c)) - radius(ub[p]));
      }
#pragma GCC unroll 9
      for (int e = 0; e < 9; ++e) {
        const V3 x = cross(ua[e / 3], ub[e % 3]);
        const B x2 = dot(x, x);
        const auto valid = x2 > B(kParallelThreshold<T> * kParallelThreshold<T>);
        const B inv = S::rsqrt(S::select(valid, x2, one));
        sep = S::max(sep, S::select(valid, (S::abs(dot(x, c)) - radius(x)) * inv, sep));
      }
      S::store(bound + k, S::max(sep, zero));
      S::store_code(hit + k, S::select(sep > zero, zero, one));
    }
  }

  // Box-triangle overlap by the separating axis test on the 13 axes (box axes, triangle
  // normal, box axes x triangle edges), fused: one flag per pair (Akenine-Moller's test).
  static void box_triangle_overlap(BoxLanes<T> box, const T* tri, int count, int N,
                                   CodeOf<T>* hit) {
    const B zero(T(0)), one(T(1));
    for (int k = 0; k < count; k += S::size) {
      V3 u[3], v[3];
      B h[3];
      for (int i = 0; i < 3; ++i) {
        u[i] = load3(box.u + 3 * i * N, N, k), h[i] = S::load(box.h + i * N + k);
        v[i] = load3(tri + 3 * i * N, N, k);
      }
      const V3 c = load3(box.c, N, k);
      // Work relative to the box centre.
      for (auto& p : v) p = V3{p.x - c.x, p.y - c.y, p.z - c.z};
      const V3 e[3] = {{v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z},
                       {v[2].x - v[1].x, v[2].y - v[1].y, v[2].z - v[1].z},
                       {v[0].x - v[2].x, v[0].y - v[2].y, v[0].z - v[2].z}};
      // An axis separates when the triangle's interval [min d, max d] misses the box's [-r, r].
      // Axes of (nearly) parallel directions are skipped: their rounding could fake a gap.
      auto separates = [&](const V3& n, const B& scale2) {
        const B d0 = dot(n, v[0]), d1 = dot(n, v[1]), d2 = dot(n, v[2]);
        const B tmax = S::max(d0, S::max(d1, d2));
        const B tmin = zero - S::max(zero - d0, S::max(zero - d1, zero - d2));
        B r(T(0));
        for (int q = 0; q < 3; ++q) r = S::fma(h[q], S::abs(dot(n, u[q])), r);
        const auto reliable = dot(n, n) > B(kParallelThreshold<T> * kParallelThreshold<T>) * scale2;
        return reliable && ((tmin > r) || (tmax < zero - r));
      };
      const B e2[3] = {dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])};
      auto out = separates(u[0], one) || separates(u[1], one) || separates(u[2], one) ||
                 separates(cross(e[0], e[1]), e2[0] * e2[1]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out = out || separates(cross(u[i], e[j]), e2[j]);
      S::store_code(hit + k, S::select(out, zero, one));
    }
  }

  // Box-triangle: 13 axes, 26 planes (see BoxTrianglePlanes).
  static void box_triangle(BoxLanes<T> box, const T* tri, int count, int N, bool difference,
                           PlaneLanes<T> out) {
    for (int k = 0; k < count; k += S::size) {
      V3 u[3], v[3];
      B h[3];
      for (int i = 0; i < 3; ++i) {
        u[i] = load3(box.u + 3 * i * N, N, k);
        h[i] = S::load(box.h + i * N + k);
        v[i] = load3(tri + 3 * i * N, N, k);
      }
      const V3 c = load3(box.c, N, k);
      const V3 e[3] = {{v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z},
                       {v[2].x - v[1].x, v[2].y - v[1].y, v[2].z - v[1].z},
                       {v[0].x - v[2].x, v[0].y - v[2].y, v[0].z - v[2].z}};
      const B e2[3] = {dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])};  // squared lengths
      B valid(0), tri_ok(0);
      const V3 nt = unit_or_zero(cross(e[0], e[1]), e2[0] * e2[1], tri_ok, T(1));
#pragma GCC unroll 13
      for (int p = 0; p < 13; ++p) {
        V3 n;
        if (p < 3) {
          n = u[p], valid = valid + B(T(1 << p));
        } else if (p == 3) {
          n = nt, valid = valid + tri_ok * B(T(1 << 3));
        } else {
          const int j = (p - 4) % 3;
          n = unit_or_zero(cross(u[(p - 4) / 3], e[j]), e2[j], valid, T(1 << p));
        }
        B s, code;
        box_support(n, u, h, s, code);
        // Triangle vertex extremes in n; ties go to the lowest index.
        const B d0 = dot(n, v[0]), d1 = dot(n, v[1]), d2 = dot(n, v[2]);
        B hi = d0, ihi(0), lo = d0, ilo(0);
        ihi = S::select(d1 > hi, B(T(1)), ihi), hi = S::max(hi, d1);
        ihi = S::select(d2 > hi, B(T(2)), ihi), hi = S::max(hi, d2);
        ilo = S::select(d1 < lo, B(T(1)), ilo), lo = S::select(d1 < lo, d1, lo);
        ilo = S::select(d2 < lo, B(T(2)), ilo), lo = S::select(d2 < lo, d2, lo);
        // A (+) T: h(n) = box + max d, h(-n) = box' - min d. A (-) T swaps the roles.
        const B plus = difference ? B(T(0)) - lo : hi, minus = difference ? hi : B(T(0)) - lo;
        const B iplus = difference ? ilo : ihi, iminus = difference ? ihi : ilo;
        const B m = dot(n, c);
        // A degenerate triangle's lane is written as zeros (tri_ok is 0 or 1).
        store3(out.n + 3 * p * N, N, k, scaled(n, tri_ok));
        S::store(out.offset + p * N + k, (s + m + plus) * tri_ok);
        S::store(out.offset + (p + 13) * N + k, (s - m + minus) * tri_ok);
        S::store_code(out.code + p * N + k, S::fma(iplus, B(T(8)), code));
        S::store_code(out.code + (p + 13) * N + k, S::fma(iminus, B(T(8)), B(T(7)) - code));
      }
      // A degenerate triangle: only bit 30 (the lane is invalid); 2^30 is exact in float and
      // fits the int32 code.
      valid = S::select(tri_ok > B(T(0)), valid, B(T(1 << 30)));
      S::store_code(out.valid + k, valid);
    }
  }

  // Exact triangle-triangle distance, one pair per lane, without branches: the least of the 9
  // edge-edge distances (closest points of segments, Ericson, "Real-Time Collision Detection",
  // 2005, 5.1.9, with its degenerate cases as selects), the 6 vertex-face distances where the
  // vertex projects into the other (non-flat) triangle, and 0 where an edge pierces the other
  // triangle's interior. Coordinates relative to the first corner of s; a lane whose span is
  // outside [kTriLow, kTriHigh] (products of four coordinates would leave the float type's
  // range) or not finite gets NaN, for the caller's scalar path.
  static constexpr T kTriLow = std::is_same_v<T, float> ? T(1e-6) : T(1e-60);
  static constexpr T kTriHigh = std::is_same_v<T, float> ? T(1e6) : T(1e60);

  struct Closest {
    B d2;
    V3 p, q;
    void take(const B& e2, const V3& a, const V3& b) {
      const auto better = e2 < d2;
      d2 = S::select(better, e2, d2);
      p = pick3(better, a, p), q = pick3(better, b, q);
    }
  };
  static V3 sub(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  static B clamp01(const B& v) { return S::max(B(T(0)), S::min(B(T(1)), v)); }
  static B safe(const B& v) { return S::select(v == B(T(0)), B(T(1)), v); }

  static void segment_pair(const V3& p0, const V3& p1, const V3& q0, const V3& q1, Closest& best) {
    const B zero(T(0)), one(T(1));
    const V3 d1 = sub(p1, p0), d2 = sub(q1, q0), r = sub(p0, q0);
    const B a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r), c = dot(d1, r), b = dot(d1, d2);
    const V3 x = cross(d1, d2);
    // a e - b^2 and b f - c e by Lagrange's identity, without the cancellation of near-parallel
    // segments (as in the scalar segment_segment).
    const B denom = dot(x, x);
    const B s0 = S::select(denom > zero, clamp01(dot(x, cross(d2, r)) / safe(denom)), zero);
    const B tn = (b * s0 + f) / safe(e);
    const B s_lo = clamp01((zero - c) / safe(a)), s_hi = clamp01((b - c) / safe(a));
    B s = S::select(tn < zero, s_lo, S::select(tn > one, s_hi, s0));
    B t = clamp01(tn);
    s = S::select(e == zero, s_lo, s), t = S::select(e == zero, zero, t);  // q is a point
    s = S::select(a == zero, zero, s);                                       // p is a point
    const V3 cp = axpy(s, d1, p0), cq = axpy(t, d2, q0);
    const V3 gap = sub(cp, cq);
    best.take(dot(gap, gap), cp, cq);
  }

  // Is x inside the triangle v (normal n, not flat)? All three edge tests >= 0.
  static auto inside(const V3 (&v)[3], const V3& n, const V3& x) {
    const B zero(T(0));
    return (dot(cross(sub(v[1], v[0]), sub(x, v[0])), n) >= zero) &&
           (dot(cross(sub(v[2], v[1]), sub(x, v[1])), n) >= zero) &&
           (dot(cross(sub(v[0], v[2]), sub(x, v[2])), n) >= zero);
  }

  // Vertex p against triangle v: the plane distance where p projects inside; and the edges of
  // the other triangle through v: 0 where one pierces v's interior. o is s unless `swap`.
  static void vertex_face(const V3 (&v)[3], const V3& n, const B& n2, const decltype(B(T(0)) < B(T(0)))& solid,
                          const V3 (&o)[3], bool swap, Closest& best) {
    const B zero(T(0)), inf(std::numeric_limits<T>::infinity());
    for (int k = 0; k < 3; ++k) {
      const B h = dot(n, sub(o[k], v[0]));
      const V3 proj = axpy(zero - h / safe(n2), n, o[k]);
      const B e2 = S::select(solid && inside(v, n, proj), h * h / safe(n2), inf);
      if (swap) best.take(e2, proj, o[k]); else best.take(e2, o[k], proj);
      // The edge o[k] -> o[k + 1] crossing v's plane strictly inside v.
      const V3& nxt = o[(k + 1) % 3];
      const B hn = dot(n, sub(nxt, v[0]));
      const auto crosses = ((h > zero) && (hn < zero)) || ((h < zero) && (hn > zero));
      const V3 x = axpy(h / safe(h - hn), sub(nxt, o[k]), o[k]);
      best.take(S::select(solid && crosses && inside(v, n, x), zero, inf), x, x);
    }
  }

  // The triangle turned cyclically so that its first corner is opposite its longest edge: the
  // normal is then the cross product of the two shortest edges, the least rounding (as the
  // scalar path's apex_first).
  static void apex_first(V3 (&v)[3]) {
    const V3 e0 = sub(v[1], v[0]), e1 = sub(v[2], v[1]), e2 = sub(v[0], v[2]);
    const B l0 = dot(e0, e0), l1 = dot(e1, e1), l2 = dot(e2, e2);
    const auto k1 = (l2 >= l0) && (l2 > l1), k2 = (l0 > l2) && (l0 > l1);  // else v0 first
    const V3 r0 = pick3(k1, v[1], pick3(k2, v[2], v[0]));
    const V3 r1 = pick3(k1, v[2], pick3(k2, v[0], v[1]));
    const V3 r2 = pick3(k1, v[0], pick3(k2, v[1], v[2]));
    v[0] = r0, v[1] = r1, v[2] = r2;
  }

  static void triangle_distance(const T* s, const T* t, int count, int N, T* dist, T* ps, T* pt) {
    const B zero(T(0)), inf(std::numeric_limits<T>::infinity());
    for (int k = 0; k < count; k += S::size) {
      const V3 o = load3(s, N, k);
      V3 a[3], b[3];
      for (int i = 0; i < 3; ++i) a[i] = sub(load3(s + 3 * i * N, N, k), o), b[i] = sub(load3(t + 3 * i * N, N, k), o);
      apex_first(a), apex_first(b);
      B span = zero;
      for (const V3* v : {&a[1], &a[2], &b[0], &b[1], &b[2]})
        span = S::max(span, S::max(S::abs(v->x), S::max(S::abs(v->y), S::abs(v->z))));
      const auto usable = (span == zero) || ((span >= B(kTriLow)) && (span <= B(kTriHigh)));
      Closest best{inf, a[0], b[0]};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) segment_pair(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], best);
      // Flat (zero-area) triangles have no face region; their edges cover them (as the scalar
      // path: |n|^2 against 1e-24 of the longest edge's to the fourth).
      const auto normal = [&](const V3 (&v)[3], B& n2, decltype(B(T(0)) < B(T(0)))& solid) {
        const V3 n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
        n2 = dot(n, n);
        const V3 e0 = sub(v[1], v[0]), e1 = sub(v[2], v[0]), e2 = sub(v[2], v[1]);
        const B longest = S::max(dot(e0, e0), S::max(dot(e1, e1), dot(e2, e2)));
        solid = n2 > B(std::is_same_v<T, float> ? T(1e-12) : T(1e-24)) * longest * longest;
        return n;
      };
      B na2, nb2;
      decltype(zero < zero) solid_a, solid_b;
      const V3 na = normal(a, na2, solid_a), nb = normal(b, nb2, solid_b);
      vertex_face(b, nb, nb2, solid_b, a, false, best);  // a's vertices and edges against b
      vertex_face(a, na, na2, solid_a, b, true, best);   // b's against a
      const B nan(std::numeric_limits<T>::quiet_NaN());
      S::store(dist + k, S::select(usable, S::sqrt(best.d2), nan));
      store3(ps, N, k, V3{best.p.x + o.x, best.p.y + o.y, best.p.z + o.z});
      store3(pt, N, k, V3{best.q.x + o.x, best.q.y + o.y, best.q.z + o.z});
    }
  }

  // Support push: per direction, max of d . v over vertices and the first index attaining it.
  static void support(const T* x, const T* y, const T* z, int n, const T* dx, const T* dy,
                      const T* dz, int K, T* max_out, int* arg_out) {
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
  static B load_u(const T* p) {
    if constexpr (S::size == 1)
      return *p;
    else
      return B::load_unaligned(p);
  }
};

// The table filled member by member, by name: a reordering of KernelTable cannot shift a kernel
// into another's slot, and a member left out stays null, which Kernels.EveryTableIsComplete
// rejects. (GCC's sanitizer builds refuse a function pointer's null test in a static_assert.)
template <class Arch>
constexpr KernelTable make_table() {
  KernelTable t{};
  t.box_box_f = &Kernels<float, Arch>::box_box;
  t.box_box_d = &Kernels<double, Arch>::box_box;
  t.box_tri_f = &Kernels<float, Arch>::box_triangle;
  t.box_tri_d = &Kernels<double, Arch>::box_triangle;
  t.support_f = &Kernels<float, Arch>::support;
  t.support_d = &Kernels<double, Arch>::support;
  t.box_box_single_d = &Kernels<double, Arch>::box_box_axes;
  t.box_box_proximity_f = &Kernels<float, Arch>::box_box_proximity;
  t.box_box_proximity_d = &Kernels<double, Arch>::box_box_proximity;
  t.box_box_separation_f = &Kernels<float, Arch>::box_box_separation;
  t.box_box_separation_d = &Kernels<double, Arch>::box_box_separation;
  t.box_triangle_overlap_f = &Kernels<float, Arch>::box_triangle_overlap;
  t.box_triangle_overlap_d = &Kernels<double, Arch>::box_triangle_overlap;
  t.box_pair_d = &BoxPairQuery<double, Arch>::box_pair;
  t.tri_tri_f = &Kernels<float, Arch>::triangle_distance;
  t.tri_tri_d = &Kernels<double, Arch>::triangle_distance;
  return t;
}


}  // namespace minksum::detail
