// The box-box proximity kernels, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"
#include "simd/separating_axes.hpp"

namespace minksum::detail {

/// A register of box pairs in A's frame, and the fused separation bound over their 15 axes.
template <class T, class Arch>
struct BoxSeparation : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::cross_accurate, L::scaled, L::load3, L::store3, L::pick, L::axpy, L::pick3;
  using typename L::S, typename L::B, typename L::V3;

  // The pair in A's frame, as SeparatingAxes takes it: C = U_A^T U_B, cA = U_A^T c, cB = U_B^T c.
  using Axes = SeparatingAxes<S, Arch>;
  struct InAFrame {
    B C[3][3], cA[3], cB[3];
    InAFrame(const V3 (&ua)[3], const V3 (&ub)[3], const V3& c) {
      for (int i = 0; i < 3; ++i) {
        cA[i] = dot(ua[i], c), cB[i] = dot(ub[i], c);
        for (int j = 0; j < 3; ++j) C[i][j] = dot(ua[i], ub[j]);
      }
    }
  };

  // The separating axis test (SeparatingAxes) fused into one pass, no planes written: is the
  // origin inside A (-) B, and a lower bound of the distance (the largest separation over the
  // 15 axes), for octree traversal and broad phases. Edge crosses closer to parallel than
  // kParallelThreshold are skipped.
  static void box_box_separation(BoxLanes<T> a, BoxLanes<T> b, int count, int N, T* bound, CodeOf<T>* hit) {
    const B zero(T(0)), one(T(1));
    const B parallel2(kParallelThreshold<T> * kParallelThreshold<T>);
    for (int k = 0; k < count; k += S::size) {
      V3 ua[3], ub[3];
      B ha[3], hb[3];
      for (int i = 0; i < 3; ++i) {
        ua[i] = load3(a.u + 3 * i * N, N, k), ub[i] = load3(b.u + 3 * i * N, N, k);
        ha[i] = S::load(a.h + i * N + k), hb[i] = S::load(b.h + i * N + k);
      }
      const V3 ca = load3(a.c, N, k), cb = load3(b.c, N, k);
      const InAFrame f(ua, ub, V3{ca.x - cb.x, ca.y - cb.y, ca.z - cb.z});
      B sep(-std::numeric_limits<T>::infinity());
      Axes::visit(
          f.C, f.cA, f.cB, ha, hb, [&](int, const B& d) { sep = S::max(sep, d); },
          [&](int, const B& d, const B& len2) {
            const auto valid = len2 > parallel2;
            sep = S::max(sep, S::select(valid, d * S::rsqrt(S::select(valid, len2, one)), sep));
          });
      S::store(bound + k, S::max(sep, zero));
      S::store_code(hit + k, S::select(sep > zero, zero, one));
    }
  }
};

/// One facet of the zonotope A (-) B for a register of box pairs: the pieces of the proximity
/// kernels below.
template <class T, class Arch>
struct BoxFacet : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::cross_accurate, L::scaled, L::load3, L::store3, L::pick, L::axpy, L::pick3;
  using typename L::S, typename L::B, typename L::V3;

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
    // The facet's normal, exact to a few ulps for the generators as rounded (the zonotope they
    // span is within rounding of M): the plain product of two nearly parallel generators
    // misses its direction by an ulp over the sine of their angle.
    const V3 x = cross_accurate(gi, gj);
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
    // The 2D least-squares problem over (a, b) in [-1, 1]^2. Its optimum (a*, b*) by Lagrange's
    // identity, G12 r2 - G22 r1 = x . (g_j x F0) and G12 r1 - G11 r2 = x . (F0 x g_i), and
    // det = G11 G22 - G12^2 = |x|^2: the Gram products cancel for nearly parallel generators
    // (an error of 1 / sin^2 of the angle in a*, b*).
    const B G11 = dot(gi, gi), G22 = dot(gj, gj), G12 = dot(gi, gj);
    const B r1 = dot(gi, F0), r2 = dot(gj, F0);
    const B det = S::select(valid, x2, one);
    const B as = dot(x, cross(gj, F0)) / det, bs = dot(x, cross(F0, gi)) / det;
    const auto a_out = S::abs(as) > one, b_out = S::abs(bs) > one;
    // Candidate on a = +-1 (if a* is beyond it) and on b = +-1 (if b* is).
    const B a1 = clamp1(as), b1 = clamp1(S::select(a_out, (zero - (r2 + a1 * G12)) / G22, bs));
    const B b2 = clamp1(bs), a2 = clamp1(S::select(b_out, (zero - (r1 + b2 * G12)) / G11, as));
    V3 p1 = axpy(b1, gj, axpy(a1, gi, F0));
    const V3 p2 = axpy(b2, gj, axpy(a2, gi, F0));
    // Inside the facet the nearest point is the origin's projection on its plane, x (x . F0) /
    // |x|^2, at the distance |x . F0| / |x|, exact to the rounding of F0. (|F0 + a* g_i + b* g_j|
    // carries the error of (a*, b*) along the facet, which still grows as 1 / sin for nearly
    // parallel generators, squared over the distance: 0.29 for boxes 0.022 apart, in float.)
    const auto inside = (S::abs(as) <= one) && (S::abs(bs) <= one);
    const B h = dot(x, F0);
    p1 = pick3(inside, scaled(x, h / det), p1);
    const B d1 = S::select(inside, h * (h / det), dot(p1, p1)), d2 = S::select(b_out, dot(p2, p2), inf);
    const auto second = d2 < d1;
    const B ab = S::select(second, a2, a1), bb = S::select(second, b2, b1);
    f.P = pick3(second, p2, p1);
    f.dist2 = S::select(valid, S::select(second, d2, d1), inf);
    // The point on A: c_A plus A's generators at their parameters.
    f.pa = ca;
    for (int q = 0; q < 3; ++q) f.pa = axpy(pick(role.is_i(q), ab, pick(role.is_j(q), bb, extreme[q])), g[q], f.pa);
    const V3 miss = axpy(-f.overlap, f.n_out, f.P);
    f.err = S::select(valid, dot(miss, miss), inf);
    return f;
  }
};

/// The choice over the facets of a register of box pairs: the pairs loaded, the facets folded.
template <class T, class Arch>
struct BoxFacetFold : BoxFacet<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::cross_accurate, L::scaled, L::load3, L::store3, L::pick, L::axpy, L::pick3;
  using typename L::S, typename L::B, typename L::V3;
  using F = BoxFacet<T, Arch>;
  using typename F::FacetEval, typename F::Mask;
  template <int I, int J>
  using FixedPair = typename F::template FixedPair<I, J>;
  using F::facet;

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

  static void generators(const V3 (&ua)[3], const B (&ha)[3], const V3 (&ub)[3], const B (&hb)[3], V3 (&g)[6]) {
    for (int i = 0; i < 3; ++i) g[i] = scaled(ua[i], ha[i]), g[3 + i] = scaled(ub[i], B(T(0)) - hb[i]);
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

  template <int P>
  static void fold_pair(Fold& fold, const PairRegister& r) {
    // The 15 generator pairs: (0,1) (0,2) (1,2) (3,4) (3,5) (4,5), then (A_i, B_j).
    constexpr int kI[15] = {0, 0, 1, 3, 3, 4, 0, 0, 0, 1, 1, 1, 2, 2, 2};
    constexpr int kJ[15] = {1, 2, 2, 4, 5, 5, 3, 4, 5, 3, 4, 5, 3, 4, 5};
    fold.add(facet(FixedPair<kI[P], kJ[P]>{}, r.c, r.ca, r.g, r.g2, r.g[kI[P]], r.g[kJ[P]]));
  }
  template <int... P>
  static void fold_all(Fold& fold, const PairRegister& r, std::integer_sequence<int, P...>) {
    (fold_pair<P>(fold, r), ...);
  }
};

/// Box-box proximity on the zonotope A (-) B, and the fused separation bound.
template <class T, class Arch>
struct BoxProximityKernels : BoxFacetFold<T, Arch>, BoxSeparation<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::cross_accurate, L::scaled, L::load3, L::store3, L::pick, L::axpy, L::pick3;
  using typename L::S, typename L::B, typename L::V3;
  using F = BoxFacetFold<T, Arch>;
  using typename F::FacetEval, typename F::Mask, typename F::LanePair, typename F::Fold, typename F::PairRegister;
  using typename BoxSeparation<T, Arch>::Axes, typename BoxSeparation<T, Arch>::InAFrame;
  template <int I, int J>
  using FixedPair = typename F::template FixedPair<I, J>;
  using F::facet, F::generators, F::fold_all;


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

  static void store_proximity(ProximityLanes<T> out, int N, int k, const B& separated, const B& distance,
                              const B& depth, const V3& dir, const V3& pa, const V3& p) {
    S::store(out.distance + k, distance);
    S::store(out.depth + k, depth);
    store3(out.direction, N, k, scaled(dir, B(T(1)) - separated));
    store3(out.point_a, N, k, pa);
    store3(out.point_b, N, k, V3{pa.x - p.x, pa.y - p.y, pa.z - p.z});
  }

  // All 15 facet pairs of one register of lanes (k .. k + S::size).
  static void proximity_all_facets(BoxLanes<T> a, BoxLanes<T> b, int N, int k, ProximityLanes<T> out) {
    const B zero(T(0)), one(T(1));
    const PairRegister r(a, b, N, k);
    Fold fold;
    fold_all(fold, r, std::make_integer_sequence<int, 15>{});
    // Separated or not is one decision, the separating axis test's: judging each facet's plane
    // on its own let rounding call one part of a facet split between parallel generator pairs
    // separating and another not, and the distance came from the wrong part (320.9 for
    // touching boxes in float). Every facet part is in M, so when separated the
    // nearest of all of them is the nearest point of M.
    const auto separated = fold.least < zero;
    store_proximity(out, N, k, S::select(separated, one, zero), S::select(separated, S::sqrt(fold.best2), zero),
                    S::select(separated, zero, fold.depth), fold.dir, pick3(separated, fold.best_pa, fold.deep_pa),
                    pick3(separated, fold.best_p, fold.deep_p));
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
    // The separating axis test chooses the facet: the axis of largest separation.
    const InAFrame af(r.ua, r.ub, r.c);
    B best(-inf), best_i(zero), best_j(zero);  // the best axis and its generator pair
    const auto keep = [&](const B& sep, int p) {
      const auto better = sep > best;
      best = S::select(better, sep, best);
      best_i = S::select(better, B(T(kI[p])), best_i), best_j = S::select(better, B(T(kJ[p])), best_j);
    };
    // Face axis i of A is spanned by generator pair 2 - i, of B by 5 - i; edge axis p by pair p.
    const B sliver2(kSliverThreshold<T> * kSliverThreshold<T>);
    Axes::visit(
        af.C, af.cA, af.cB, r.ha, r.hb, [&](int p, const B& d) { keep(d, p < 3 ? 2 - p : 8 - p); },
        [&](int p, const B& d, const B& len2) {
          const auto ok = len2 > sliver2;
          keep(S::select(ok, d * S::rsqrt(S::select(ok, len2, one)), -inf), p);
        });
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
    const auto proven =
        (separated && low >= f.dist2 - dist * tol) || (best <= zero && f.overlap < inf && f.err <= tol * tol);
    const B nan(std::numeric_limits<T>::quiet_NaN());
    store_proximity(out, N, k, S::select(separated, one, zero), S::select(proven, dist, nan),
                    S::select(separated, zero, f.overlap), f.n_out, f.pa, f.P);
  }

  // One pair per lane: the fast path, then the lanes it could not prove through all facets,
  // gathered S::size at a time into local lanes.
  static void box_box_proximity(BoxLanes<T> a, BoxLanes<T> b, int count, int N, ProximityLanes<T> out) {
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
};

}  // namespace minksum::detail
