// The exact proximity of one box pair without building A (-) B: the separating axis test picks
// the facet of the zonotope M = A (-) B = c + G t (t in [-1, 1]^6) nearest the origin's side,
// and an active-set walk from that facet finds M's closest point (distance) or the preimage of
// the deepest boundary point (penetration). Scalar and templated on the float type: one pair is
// too little work for SIMD lanes; the batched kernels cover many pairs.
#pragma once

#include "simd/box_pair_data.hpp"
#include "simd/separating_axes.hpp"
#include "simd/simd.hpp"

#include <cmath>
#include <limits>

namespace minksum::detail {

template <class T>
struct SatResult {
  T separation;        // largest separation over the axes (negative: the smallest overlap)
  T normal[3];         // its unit normal, outward from M on the origin's side
  unsigned free_mask;  // the two generators spanning that facet
};

// Scalar code on small arrays: GCC's straight-line (SLP) vectoriser packs neighbouring
// elements into vector loads of data that was just stored element by element, and such loads
// stall (store forwarding fails); this code is kept scalar.
#if defined(__GNUC__) && !defined(__clang__)
#define MINKSUM_SCALAR_CODE __attribute__((optimize("no-tree-slp-vectorize")))
#else
#define MINKSUM_SCALAR_CODE
#endif

// The box-pair query, compiled once per ISA translation unit, in four parts by job. Arch tells
// the copies apart: every function is a member, so no inline function is shared between
// translation units compiled with different instruction sets (the linker would keep any one
// copy of it).

/// The small vector products of the pair's parts.
template <class T, class Arch>
struct BoxPairMath {
  static T dot3(const T* x, const T* y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; }
  static void cross(const T* a, const T* b, T (&x)[3]) {
    x[0] = a[1] * b[2] - a[2] * b[1], x[1] = a[2] * b[0] - a[0] * b[2], x[2] = a[0] * b[1] - a[1] * b[0];
  }
  // a x b to a few ulps of each component (Lanes::cross_accurate, one value): the plain
  // product of generators sin t apart errs by an ulp of |a| |b|, 1 / sin t of the result's.
  static void cross_accurate(const T* a, const T* b, T (&x)[3]) {
    for (int d = 0; d < 3; ++d) {
      const int i = (d + 1) % 3, j = (d + 2) % 3;
      x[d] = minor_accurate<T, Arch>(a[i], b[j], a[j], b[i]);
    }
  }
};

/// The zonotope M = A (-) B of a box pair, loaded, and the separating axis test on it.
template <class T, class Arch>
struct BoxPairSat : BoxPairMath<T, Arch> {
  using BoxPairMath<T, Arch>::dot3;
  using BoxPairMath<T, Arch>::cross;
  using BoxPairMath<T, Arch>::cross_accurate;

  // The zonotope A (-) B of boxes a and b, computed from locals and stored once: reading back
  // what was just stored element by element with wider loads stalls (store forwarding fails).
  MINKSUM_SCALAR_CODE static void load(const BoxLanes<double>& a, const BoxLanes<double>& b, BoxPair<T>& p) {
    T u[6][3], h[6], c[3];
    for (int d = 0; d < 3; ++d) c[d] = T(a.c[d] - b.c[d]), p.ca[d] = T(a.c[d]);
    for (int k = 0; k < 3; ++k) {
      h[k] = T(a.h[k]), h[3 + k] = T(b.h[k]);
      for (int d = 0; d < 3; ++d) u[k][d] = T(a.u[3 * k + d]), u[3 + k][d] = T(b.u[3 * k + d]);
    }
    for (int k = 0; k < 6; ++k) {
      p.h[k] = h[k];
      p.uc[k] = dot3(u[k], c);
      for (int d = 0; d < 3; ++d) p.u[k][d] = u[k][d], p.g[k][d] = (k < 3 ? h[k] : -h[k]) * u[k][d];
    }
    for (int d = 0; d < 3; ++d) p.c[d] = c[d];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) p.C[i][j] = dot3(u[i], u[3 + j]);
  }

  // An edge axis's separation d and |L|^2 from the accurate cross L = u_Ai x u_Bj and the
  // axes as given, |L . c| - sum_k h_k |L . u_k|, where |L|^2 < kNearParallel2.
  [[gnu::noinline]] static void near_parallel_axis(const BoxPair<T>& p, int axis, T& d, T& len2) {
    T x[3];
    cross_accurate(p.u[(axis - 6) / 3], p.u[3 + (axis - 6) % 3], x);
    T r = 0;
    for (int k = 0; k < 6; ++k) r += p.h[k] * std::abs(dot3(x, p.u[k]));
    d = std::abs(dot3(x, p.c)) - r, len2 = dot3(x, x);
  }

  // The separating axis test over the 15 axes (SeparatingAxes): the axis with the largest
  // separation (negative: the smallest overlap), formed once at the end. Edge crosses closer
  // to parallel than kSliverThreshold are skipped (see box_box_proximity).
  MINKSUM_SCALAR_CODE static SatResult<T> separating_axis(const BoxPair<T>& p) {
    // Axes are compared without a square root or a division per axis, by the signed square
    // d |d| / len2 of the separation d / sqrt(len2) (monotone in it), cross-multiplied: axis
    // (d, len2) beats the best (bd, bl) iff d |d| bl > bd |bd| len2. Each is compared where it
    // is computed: arrays of them read back as vectors stall on store forwarding.
    T bd = -std::numeric_limits<T>::infinity(), bkey = bd, bl = 1;
    int w = 0;
    const T sliver2 = kSliverThreshold<T> * kSliverThreshold<T>;
    SeparatingAxes<Simd<T, ScalarArch>, Arch>::visit(
        p.C, p.uc, p.uc + 3, p.h, p.h + 3,
        [&](int axis, T d) {
          if (d > bd) bd = d, bkey = d * std::abs(d), w = axis;  // (bl is 1 until an edge wins)
        },
        [&](int axis, T d, T len2) {
          if ((len2 < kNearParallel2<T>) & (len2 > sliver2)) [[unlikely]]
            near_parallel_axis(p, axis, d, len2);
          const T key = d * std::abs(d);
          if (len2 > sliver2 && key * bl > bkey * len2) bd = d, bkey = key, bl = len2, w = axis;
        });
    SatResult<T> out;
    T n[3];
    if (w < 6) {
      for (int d = 0; d < 3; ++d) n[d] = p.u[w][d];
      out.free_mask = w < 3 ? 7u & ~(1u << w) : 56u & ~(1u << w);
    } else {
      const T* a = p.u[(w - 6) / 3];
      const T* b = p.u[3 + (w - 6) % 3];
      if (bl < kNearParallel2<T>)
        cross_accurate(a, b, n);
      else
        n[0] = a[1] * b[2] - a[2] * b[1], n[1] = a[2] * b[0] - a[0] * b[2], n[2] = a[0] * b[1] - a[1] * b[0];
      out.free_mask = (1u << (w - 6) / 3) | (8u << (w - 6) % 3);
    }
    const T inv = T(1) / std::sqrt(bl);
    out.separation = bd * inv;
    // Outward facet normal on the origin's side: against c.
    const T s = dot3(n, p.c) > 0 ? -inv : inv;
    for (int d = 0; d < 3; ++d) out.normal[d] = s * n[d];
    return out;
  }

  // What the warm path reads of the pair: c, ca, h and the generators (not C nor u . c).
  MINKSUM_SCALAR_CODE static void load_generators(const BoxLanes<double>& a, const BoxLanes<double>& b, BoxPair<T>& p) {
    for (int d = 0; d < 3; ++d) p.c[d] = T(a.c[d] - b.c[d]), p.ca[d] = T(a.c[d]);
    for (int k = 0; k < 3; ++k) {
      p.h[k] = T(a.h[k]), p.h[3 + k] = T(b.h[k]);
      for (int d = 0; d < 3; ++d) p.g[k][d] = T(a.h[k] * a.u[3 * k + d]), p.g[3 + k][d] = T(-b.h[k] * b.u[3 * k + d]);
    }
  }
};

/// The active-set walk to M's point nearest a target.
template <class T, class Arch>
struct BoxPairWalk : BoxPairMath<T, Arch> {
  using BoxPairMath<T, Arch>::dot3;
  using BoxPairMath<T, Arch>::cross;
  using BoxPairMath<T, Arch>::cross_accurate;

  /// The point of M = c + G t nearest to the point q, t in [-1, 1]^6: bounded-variable least
  /// squares min |c - q + G t|^2 by the active-set method of Stark & Parker ("Bounded-variable
  /// least squares", Computational Statistics 10, 1995; Lawson & Hanson 1974, ch. 23), started
  /// with t at a vertex and `free_mask` free. At most 3 generators are free at a time: three
  /// independent ones reach q. Returns false if it did not settle within its iteration budget
  /// (never seen; the caller then has a feasible t, i.e. an upper bound).
  /// `trust_start`: the start facet is the SAT's, so q projecting into it is optimal at once;
  /// a warm start from another tick's active set is always checked (KKT).
  MINKSUM_SCALAR_CODE static bool nearest_point(const BoxPair<T>& p, const T (&q)[3], T (&t)[6], unsigned& free_mask,
                                                bool trust_start) {
    const T eps = std::is_same_v<T, float> ? T(1e-5) : T(1e-12);
    T base[3];  // c - q
    for (int d = 0; d < 3; ++d) base[d] = p.c[d] - q[d];
    T noise = std::abs(base[0]) + std::abs(base[1]) + std::abs(base[2]);
    for (int k = 0; k < 6; ++k) noise += p.h[k];
    noise *= 64 * std::numeric_limits<T>::epsilon();
    // c - q + the generators outside `skip` at their parameters.
    const auto residual = [&](unsigned skip, T(&r)[3]) {
      T w[6];
      for (int k = 0; k < 6; ++k) w[k] = (skip >> k & 1) ? T(0) : t[k];
      for (int d = 0; d < 3; ++d)
        r[d] = base[d] + w[0] * p.g[0][d] + w[1] * p.g[1][d] + w[2] * p.g[2][d] + w[3] * p.g[3][d] + w[4] * p.g[4][d] +
               w[5] * p.g[5][d];
    };
    unsigned blocked = 0;  // generators found dependent on the free ones (no KKT progress)
    int newest = -1;       // the generator freed last: the one to drop if the system is singular
    const auto drop = [&](const int(&f)[3], int m) {
      const int k = (newest >= 0 && (free_mask >> newest & 1)) ? newest : f[m - 1];
      free_mask &= ~(1u << k), blocked |= 1u << k;
    };
    bool first = trust_start;
    for (int iter = 0; iter < 24; ++iter) {
      // Solve for the free parameters with the others fixed; step back to the box if needed.
      for (;;) {
        int f[3], m = 0;
        for (int k = 0; k < 6; ++k)
          if (free_mask >> k & 1) {
            if (m == 3) return false;  // four free generators: cannot happen (rank 3)
            f[m++] = k;
          }
        if (m == 0) break;
        T r0[3];
        residual(free_mask, r0);
        T z[3];
        const T* g0 = p.g[f[0]];
        if (m == 1) {
          z[0] = -dot3(g0, r0) / dot3(g0, g0);
        } else if (m == 2) {
          const T* g1 = p.g[f[1]];
          const T G00 = dot3(g0, g0), G11 = dot3(g1, g1);
          T x[3], w0[3], w1[3];
          cross_accurate(g0, g1, x);
          const T det = dot3(x, x);              // G00 G11 - G01^2 without the cancellation
          if (!(det > eps * eps * G00 * G11)) {  // parallel: one of them is enough
            drop(f, m);
            continue;
          }
          // The normal equations' right-hand sides by Lagrange's identity: G11 b0 - G01 b1 =
          // x . (g1 x r0) and G00 b1 - G01 b0 = x . (r0 x g0), b = -G^T r0. The Gram products
          // cancel for nearly parallel generators (an error of 1 / sin^2 of their angle in z:
          // 0.0167 for boxes 0.0048 apart, turned by 1e-6).
          cross(g1, r0, w0), cross(r0, g0, w1);
          z[0] = dot3(x, w0) / det, z[1] = dot3(x, w1) / det;
        } else {
          const T* g1 = p.g[f[1]];
          const T* g2 = p.g[f[2]];
          // Three independent generators reach r = 0: solve G_F z = -r0 (Cramer's rule).
          T x12[3], x20[3], x01[3];
          cross(g1, g2, x12), cross(g2, g0, x20), cross(g0, g1, x01);
          const T det = dot3(g0, x12);
          const T scale = std::sqrt(dot3(g0, g0) * dot3(g1, g1) * dot3(g2, g2));
          if (!(std::abs(det) > eps * scale)) {
            drop(f, m);  // coplanar: the newest one adds nothing (its KKT slack is rounding)
            continue;
          }
          z[0] = -dot3(r0, x12) / det, z[1] = -dot3(r0, x20) / det, z[2] = -dot3(r0, x01) / det;
        }
        // Feasible: take it. Otherwise move towards z until the first parameter hits +-1, and fix
        // it there (the objective still decreases along the segment: it is convex).
        T alpha = 1;
        int hit = -1;
        for (int a = 0; a < m; ++a) {
          if (std::abs(z[a]) <= 1) continue;
          const T bound = z[a] > 0 ? T(1) : T(-1);
          const T s = (bound - t[f[a]]) / (z[a] - t[f[a]]);
          if (s < alpha) alpha = s, hit = a;
        }
        for (int a = 0; a < m; ++a) t[f[a]] += alpha * (z[a] - t[f[a]]);
        // q projects into the start facet: r is along its normal, optimal without a KKT check.
        if (hit < 0 && first && m == 2) return true;
        first = false;
        if (hit < 0) break;
        t[f[hit]] = z[hit] > 0 ? T(1) : T(-1);
        free_mask &= ~(1u << f[hit]);
      }
      // Optimality (KKT): no fixed parameter can move inwards and reduce |r|.
      T r[3];
      residual(0, r);
      const T rn = std::sqrt(dot3(r, r));
      // Below rounding of r (when q is on M, as for the deepest point), nothing can improve.
      int enter = -1;
      T worst = eps * rn + noise;
      for (int k = 0; k < 6; ++k) {
        if ((free_mask | blocked) >> k & 1) continue;
        const T slope = t[k] * dot3(p.g[k], r) / p.h[k];  // > 0: moving t_k inwards helps
        if (slope > worst) worst = slope, enter = k;
      }
      if (enter < 0) return true;
      free_mask |= 1u << enter;
      newest = enter, blocked = 0;
    }
    return false;
  }
};

/// The query: loads the pair, answers from the last active set or cold, and writes the answer.
template <class T, class Arch>
struct BoxPairQuery : BoxPairSat<T, Arch>, BoxPairWalk<T, Arch> {
  using BoxPairMath<T, Arch>::dot3;
  using BoxPairSat<T, Arch>::load;
  using BoxPairSat<T, Arch>::load_generators;
  using BoxPairSat<T, Arch>::separating_axis;
  using BoxPairWalk<T, Arch>::nearest_point;

  /// Loads the pair and answers to `level`: from the active set `active` if it is one
  /// (kActiveSet) and proves optimal for separated boxes (out.warm; then p holds only what
  /// that path reads), else cold. `active` returns the answer's active set (0 when the boxes
  /// overlap: the next query starts cold; unchanged by a verdict, which the separating axis
  /// test decides at once).
  MINKSUM_SCALAR_CODE static void box_pair(const BoxLanes<double>& a, const BoxLanes<double>& b, PairLevel level,
                                           unsigned& active, BoxPair<T>& p, PairAnswer<T>& out) {
    out.warm = false;
    if (level >= PairLevel::Distance && (active & kActiveSet)) {
      load_generators(a, b, p);
      if (warm(p, active, out)) return;  // (p holds c, ca, h and g only)
    }
    load(a, b, p);
    if (level != PairLevel::Load) run(p, level, out, active);
  }

  // M's point c + G t and its preimages: A's point and B's (= A's - M's).
  MINKSUM_SCALAR_CODE static void write_points(const BoxPair<T>& p, const T (&t)[6], T (&m)[3], PairAnswer<T>& out) {
    for (int d = 0; d < 3; ++d) {
      out.point_a[d] = p.ca[d] + t[0] * p.g[0][d] + t[1] * p.g[1][d] + t[2] * p.g[2][d];
      m[d] = p.c[d] + t[0] * p.g[0][d] + t[1] * p.g[1][d] + t[2] * p.g[2][d] + t[3] * p.g[3][d] + t[4] * p.g[4][d] +
             t[5] * p.g[5][d];
      out.point_b[d] = out.point_a[d] - m[d];
    }
  }

  static unsigned encode(const T (&t)[6], unsigned free_mask) {
    unsigned signs = 0;
    for (int k = 0; k < 6; ++k) signs |= unsigned(t[k] > 0) << (8 + k);
    return kActiveSet | signs | (free_mask & 63u);
  }

  /// The coherent path: the nearest point of M to the origin from the last answer's active
  /// set. Kept only when the walk ends with the KKT conditions met (the point is M's nearest:
  /// the problem is convex) and the distance clears what the cold path's verdict could
  /// differ by: the sliver facets the SAT skips (kSliverThreshold of the longest half
  /// extent) and rounding. Then the cold query's verdict is also "separated", at the same
  /// distance.
  MINKSUM_SCALAR_CODE static bool warm(const BoxPair<T>& p, unsigned& active, PairAnswer<T>& out) {
    T t[6];
    for (int k = 0; k < 6; ++k) t[k] = (active >> (8 + k) & 1) ? T(1) : T(-1);
    unsigned free_mask = active & 63u;
    const T origin[3] = {0, 0, 0};
    if (!nearest_point(p, origin, t, free_mask, false)) return false;
    T m[3];
    write_points(p, t, m, out);
    const T d = std::sqrt(dot3(m, m));
    T hmax = 0, reach = std::abs(p.c[0]) + std::abs(p.c[1]) + std::abs(p.c[2]);
    for (int k = 0; k < 6; ++k) hmax = std::max(hmax, p.h[k]), reach += p.h[k];
    const T guard = 4 * kSliverThreshold<T> * hmax + 256 * std::numeric_limits<T>::epsilon() * reach;
    if (!(d > guard)) return false;
    out.intersecting = false, out.distance = d, out.depth = 0;
    for (int dd = 0; dd < 3; ++dd) out.direction[dd] = 0;
    out.converged = out.warm = true;
    active = encode(t, free_mask);
    return true;
  }

  /// The exact proximity of one box pair to `level`, written field by field into out (a struct
  /// copy would read back the fields just stored, with wide loads that stall).
  MINKSUM_SCALAR_CODE static void run(const BoxPair<T>& p, PairLevel level, PairAnswer<T>& out, unsigned& active) {
    out.distance = out.depth = 0;
    for (int d = 0; d < 3; ++d) out.direction[d] = 0;
    const SatResult<T> sat = separating_axis(p);
    T target[3] = {0, 0, 0};
    // Touching within rounding (64 eps of the coordinates, as the general path) counts as
    // intersecting: a box resting on a box, posed, is apart or pressed by a few ulps.
    T reach = std::abs(p.c[0]) + std::abs(p.c[1]) + std::abs(p.c[2]);
    for (int k = 0; k < 6; ++k) reach += p.h[k];
    for (int d = 0; d < 3; ++d) reach += std::abs(p.ca[d]);
    out.intersecting = !(sat.separation > 64 * std::numeric_limits<T>::epsilon() * reach);
    out.converged = true;
    if (level == PairLevel::Verdict) return;
    if (out.intersecting) {
      // The deepest point: the origin's projection onto the nearest facet, depth * normal.
      out.depth = std::max(T(0), -sat.separation);
      for (int d = 0; d < 3; ++d) out.direction[d] = sat.normal[d], target[d] = out.depth * sat.normal[d];
      if (level == PairLevel::Distance) return void(active = 0);  // (its preimage gives the witnesses only)
    }
    T t[6];  // the facet's vertex, where the walk starts
    for (int k = 0; k < 6; ++k) t[k] = dot3(sat.normal, p.g[k]) >= 0 ? T(1) : T(-1);
    unsigned free_mask = sat.free_mask;
    out.converged = nearest_point(p, target, t, free_mask, true);
    T m[3];
    write_points(p, t, m, out);
    if (!out.intersecting) out.distance = std::sqrt(dot3(m, m));
    active = !out.intersecting && out.converged ? encode(t, free_mask) : 0u;
  }
};

}  // namespace minksum::detail
