// The box-box sum kernels, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"

namespace minksum::detail {

/// The box-box sum's pieces shared by its kernels: the facets' vertex loops and the boxes'
/// corners.
template <class T, class Arch>
struct BoxBoxParts : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::scaled, L::load3, L::store3, L::inv_len_or_zero, L::box_support, L::with_row_stride;
  using typename L::S, typename L::B, typename L::V3;

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
      return plus ? V3{x.x + g[a].x, x.y + g[a].y, x.z + g[a].z} : V3{x.x - g[a].x, x.y - g[a].y, x.z - g[a].z};
    };
    const V3 x[2] = {step(c, 0, false), step(c, 0, true)};
    V3 y[4];
    for (int i = 0; i < 4; ++i) y[i] = step(x[i & 1], 1, i & 2);
    for (int i = 0; i < 8; ++i) store3(corner + 3 * i * N, N, 0, step(y[i & 3], 2, i & 4));
  }
};

/// Box-box sums: the 30 support planes of each lane's pair, and their loops and corners.
template <class T, class Arch>
struct BoxBoxKernels : BoxBoxParts<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::scaled, L::load3, L::store3, L::inv_len_or_zero, L::box_support, L::with_row_stride;
  using typename L::S, typename L::B, typename L::V3;
  using BoxBoxParts<T, Arch>::sum_loops;
  using BoxBoxParts<T, Arch>::box_corners;

  // Box-box: 15 axes, 30 planes (see BoxBoxPlanes), worked in A's frame, where A's axes are
  // e_0, e_1, e_2 and B's are the columns of C = U_A^T U_B (the OBB separating-axis formulation
  // of Gottschalk, Lin and Manocha, "OBBTree", SIGGRAPH 1996). The edge axis e_i x C_j then has
  // two nonzero components, -C[i2][j] and C[i1][j] (i1, i2 = i + 1, i + 2 mod 3), and every dot
  // product the plane needs is formed from those same two numbers: the normal and its offset
  // stay consistent (no rounding error divided by |u_i x v_j| for nearly parallel edges), and all
  // of it is linear in the unnormalised axis, so the dot products run while 1/|axis| is
  // computed. The normal is taken back to the world frame as U_A times the A-frame axis.
  static void box_box(BoxLanes<T> a, BoxLanes<T> b, int count, int N, bool difference, PlaneLanes<T> out,
                      SumLanes<T> sum) {
    with_row_stride(N, [&](auto R) { box_box_rows<R.value>(a, b, count, N, difference, out, sum); });
  }
  // R: the row stride N fixed at compile time, or 0 (any N).
  template <int R>
  static void box_box_rows(BoxLanes<T> a, BoxLanes<T> b, int count, int any_N, bool difference, PlaneLanes<T> out,
                           SumLanes<T> sum) {
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
        emit(p, ua(p), ha(p) + S::fma(hb(0), A[p][0], S::fma(hb(1), A[p][1], hb(2) * A[p][2])), cA[p], B(T(1 << p)),
             bit(C[p][0] > zero, 3) + bit(C[p][1] > zero, 4) + bit(C[p][2] > zero, 5));
        const V3 v = ub(p);
        emit(3 + p, v, hb(p) + S::fma(ha(0), A[0][p], S::fma(ha(1), A[1][p], ha(2) * A[2][p])), dot(v, c),
             bit(C[0][p] > zero, 0) + bit(C[1][p] > zero, 1) + bit(C[2][p] > zero, 2), B(T(8 << p)));
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
};

/// The single-pair API: one box pair with its 15 axes in the lanes.
template <class T, class Arch>
struct BoxBoxAxes : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::scaled, L::load3, L::store3, L::inv_len_or_zero, L::box_support, L::with_row_stride;
  using typename L::S, typename L::B, typename L::V3;

  // One box pair with its 15 axes in the lanes (16 with a padding lane): the single-pair API,
  // built from the same helpers as box_box. in = c_A, c_B (3 each), the axes u_A0..2, u_B0..2
  // (3 each), h_A, h_B (3 each). Out, per axis lane q: n[d * 16 + q], off[q] (plane +n),
  // off[16 + q] (plane -n), code[q] as in BoxBoxPlanes, valid[q] in {0, 1}.
  static void box_box_axes(const T* in, bool difference, T* n, T* off, CodeOf<T>* code, CodeOf<T>* valid) {
    const T* u = in + 6;  // axis k of the six at u[3k..3k+2]
    // Per lane: the face axis itself (kFace), or the two edge directions whose cross is the axis
    // (kE of A, kF of B); kFixA/kFixB: the codes a face axis fixes (own bit set, the rest are
    // ties, left clear; -1: computed). Lane 15 pads.
    static constexpr int kFace[16] = {0, 1, 2, 3, 4, 5, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    static constexpr int kE[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 2, 2, 2, 0};
    static constexpr int kF[16] = {4, 4, 4, 4, 4, 4, 3, 4, 5, 3, 4, 5, 3, 4, 5, 4};
    alignas(64) static constexpr T kIsFace[16] = {1, 1, 1, 1, 1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    alignas(64) static constexpr T kFixA[16] = {1, 2, 4, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
    alignas(64) static constexpr T kFixB[16] = {-1, -1, -1, 1, 2, 4, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1};
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
      const V3 v{S::select(face_lane, fc.x, x.x), S::select(face_lane, fc.y, x.y), S::select(face_lane, fc.z, x.z)};
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
};

}  // namespace minksum::detail
