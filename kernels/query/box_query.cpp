// The box-box query through the pair kernel (simd/box_pair.hpp): its active set from the last
// answer, the 15-facet fallback where the set does not settle, the farthest pair in closed
// form, and pairs scaled to lengths near 1; the patch's witnesses, the cache, and the public
// box-box entry points.
#include "query/box_query.hpp"

#include <minksum/kernels.hpp>

#include "core/scale.hpp"
#include "query/cache_kinds.hpp"
#include "query/patch.hpp"
#include "simd/box_pair_data.hpp"

#include <algorithm>
#include <cmath>

namespace minksum {

using Eigen::Vector3d;

namespace {

// The farthest pair of two boxes: the farthest vertex of M = c + G t. For a fixed corner t_A of
// A, |p + G_B t_B|^2 with p = c + G_A t_A separates into one term per axis of B (its axes are
// orthogonal), so the best t_B has the signs of g_Bj . p; compare the 8 corners of A by
// 2 t_A . (h_A u_A . c) + 2 sum_j |g_Bj . p|, the rest being the same for all.
void box_box_farthest(const detail::BoxPair<double>& p, Proximity& out) {
  double gbc[3], gab[3][3];
  for (int j = 0; j < 3; ++j) {
    gbc[j] = Vector3d(p.g[3 + j]).dot(Vector3d(p.c));
    for (int i = 0; i < 3; ++i) gab[i][j] = Vector3d(p.g[i]).dot(Vector3d(p.g[3 + j]));
  }
  double best = -std::numeric_limits<double>::infinity(), t[6] = {};
  for (int code = 0; code < 8; ++code) {
    const double s[3] = {code & 1 ? 1.0 : -1.0, code & 2 ? 1.0 : -1.0, code & 4 ? 1.0 : -1.0};
    double value = 0, tb[3];
    for (int j = 0; j < 3; ++j) {
      const double gp = gbc[j] + s[0] * gab[0][j] + s[1] * gab[1][j] + s[2] * gab[2][j];
      tb[j] = gp >= 0 ? 1 : -1;
      value += 2 * std::abs(gp) + 2 * s[j] * p.h[j] * p.uc[j];
    }
    if (value > best) best = value, t[0] = s[0], t[1] = s[1], t[2] = s[2], t[3] = tb[0], t[4] = tb[1], t[5] = tb[2];
  }
  Vector3d m(p.c), fa(p.ca);
  for (int k = 0; k < 6; ++k) {
    const Vector3d g(p.g[k]);
    m += t[k] * g;
    if (k < 3) fa += t[k] * g;
  }
  out.max_distance = m.norm(), out.far_a = fa, out.far_b = fa - m;
}

// The 15-facet evaluation of the batched kernel on one lane: the fallback if the active set
// does not settle.
Status box_box_exhaustive(const Box& a, const Box& b, Proximity& out) {
  BoxBatch<double, kLaneMultiple> A, B;
  BoxBoxProximity<double, kLaneMultiple> r;
  A.set_one(a), B.set_one(b);
  box_box_proximity(A, B, r);
  out.intersecting = !(r.distance[0] > 0);
  out.distance = r.distance[0];
  out.penetration_depth = r.depth[0];
  for (int d = 0; d < 3; ++d) {
    out.penetration_direction[d] = r.direction[d][0];
    out.point_a[d] = r.point_a[d][0], out.point_b[d] = r.point_b[d][0];
  }
  return Status::Ok;
}


// The box pair query on valid boxes whose lengths are near 1, from the active set `active`
// (0: cold); returns whether the answer came from it, and leaves the answer's active set there.
bool pair_proximity(const Box& a, const Box& b, Proximity& out, Want want, unsigned& active) {
  using detail::PairLevel;
  const PairLevel level = has(want, Want::Witnesses)  ? PairLevel::Witnesses
                          : has(want, Want::Distance) ? PairLevel::Distance
                          : has(want, Want::Verdict)  ? PairLevel::Verdict
                                                      : PairLevel::Load;
  detail::BoxPair<double> pair;
  detail::PairAnswer<double> r;
  detail::box_pair_proximity(a, b, level, active, pair, r);
  if (level != PairLevel::Load && !r.converged) {
    box_box_exhaustive(a, b, out);
  } else if (level != PairLevel::Load) {
    out.intersecting = r.intersecting;
    if (level >= PairLevel::Distance) {
      out.distance = r.distance;
      out.penetration_depth = r.depth;
      out.penetration_direction = Vector3d(r.direction);
    }
    if (level == PairLevel::Witnesses) out.point_a = Vector3d(r.point_a), out.point_b = Vector3d(r.point_b);
  }
  if (has(want, Want::MaxDistance) && r.warm) {  // the warm path loaded only part of the pair
    unsigned none = 0;
    detail::PairAnswer<double> unused;
    detail::box_pair_proximity(a, b, PairLevel::Load, none, pair, unused);
  }
  if (has(want, Want::MaxDistance)) box_box_farthest(pair, out);
  return r.warm;
}

}  // namespace

namespace {

// The box pair query on checked boxes, scaled when the lengths are far from 1.
void box_query(const Box& a, const Box& b, Proximity& out, Want want, unsigned& active, bool& warm) {
  out = Proximity{};
  warm = false;
  // Lengths far from 1 over- or underflow in the products of the pair computation (NaN for a
  // box of 1e-312 next to one of 200): then it works relative to A's
  // centre, scaled by a power of two (exact), with half extents below 2^-100 (1e-30) of the
  // pair's size raised to that (the answer moves by less), and the answer is scaled back.
  const Vector3d o = a.center;
  const double big =
      std::max({(b.center - o).cwiseAbs().maxCoeff(), a.half_extents.maxCoeff(), b.half_extents.maxCoeff()});
  const double speck = big * 0x1p-100;  // exact (big is normal here or the test fails anyway)
  if (big > 1e-60 && big < 1e60 && a.half_extents.minCoeff() >= speck && b.half_extents.minCoeff() >= speck) {
    warm = pair_proximity(a, b, out, want, active);
    return;
  }
  // Such pairs are answered cold.
  const double k = detail::scale_to_one(big);
  Box sa = a, sb = b;
  sa.center.setZero(), sb.center = k * (b.center - o);
  for (Box* x : {&sa, &sb}) x->half_extents = (k * x->half_extents).cwiseMax(std::ldexp(k * big, -100));
  active = 0;
  pair_proximity(sa, sb, out, want, active);
  active = 0;
  out.distance /= k, out.penetration_depth /= k, out.max_distance /= k;
  for (Vector3d* p : {&out.point_a, &out.point_b, &out.far_a, &out.far_b}) *p = *p / k + o;
}


// Box pairs whose nearest (or deepest) sets are patches, a face or an edge of each across the
// contact normal (a box resting, sliding or rocking on a box): the witnesses are the patch's
// (patch_point), as for prepared shapes, so that they do not jump between corners and
// the coherent answer's equal the cold one's. The normal is snapped to the axis of A or B it
// is within 1.4e-6 rad of (the box pair's normal of a 1e-12 gap is turned by rounding / gap)
// where that still proves the answer: the gap between the boxes' levels along it is the
// distance (or the depth) to 64 eps of the coordinates; else the pair's normal, if that does.
void box_patch(const Box& a, const Box& b, Proximity& out) {
  Vector3d n = out.intersecting ? out.penetration_direction : Vector3d(out.point_b - out.point_a);
  if (!(n.norm() > 0)) return;
  n.normalize();
  double align = 0;
  Vector3d axis = n;
  for (const Box* x : {&a, &b})
    for (int k = 0; k < 3; ++k)
      if (const double d = n.dot(x->rotation.col(k)); std::abs(d) > align)
        align = std::abs(d), axis = (d < 0 ? -1.0 : 1.0) * x->rotation.col(k);
  const double reach = std::max(
      {a.center.cwiseAbs().maxCoeff() + a.half_extents.sum(), b.center.cwiseAbs().maxCoeff() + b.half_extents.sum()});
  const double eps = std::numeric_limits<double>::epsilon();
  const double tau = 256 * eps * reach, gap = out.intersecting ? -out.penetration_depth : out.distance;
  for (int snapped = 1; snapped >= 0; --snapped) {
    if (snapped && !(align > 1 - 1e-12)) continue;
    const Vector3d m = snapped ? Vector3d(axis.normalized()) : n;
    detail::BoxLevel la, lb;
    if (!detail::box_level_of(a, m, 1.0, tau, la) || !detail::box_level_of(b, m, -1.0, tau, lb)) continue;
    // A corner: the pair's witnesses are the only ones (most poses end here, before the sets).
    if (la.nfree == 0 || lb.nfree == 0) return;
    const Vector3d u = m.unitOrthogonal(), w = m.cross(u);
    detail::Patch P, Q;
    detail::level_patch(a, la, tau, u, w, P), detail::level_patch(b, lb, tau, u, w, Q);
    if (P.size == 1 || Q.size == 1) return;  // (a speck of an edge or face, settled to a point)
    const double top = m.dot(la.base), bottom = m.dot(lb.base);
    if (!(std::abs(bottom - top - gap) <= 64 * eps * reach)) continue;
    Eigen::Vector2d x;
    if (!detail::patch_point(P, Q, tau, x)) return;
    out.point_a = x.x() * u + x.y() * w + top * m;
    out.point_b = out.point_a + (bottom - top) * m;
    return;
  }
}

}  // namespace

namespace {

// Both box queries on boxes already checked (a prepared box placed by a checked pose is: its
// rotation is the product of two checked ones), through the active set of `cache` if given;
// the patch's witnesses where asked.
void answer(const Box& a, const Box& b, ProximityCache* cache, Proximity& out, Want want) {
  unsigned active = cache && cache->kind == detail::kCacheBoxBox ? cache->active : 0u;
  bool warm = false;
  box_query(a, b, out, want, active, warm);
  if (has(want, Want::Patch)) box_patch(a, b, out);
  if (!cache) return;
  cache->kind = detail::kCacheBoxBox, cache->active = active;
  ++(warm ? cache->warm : cache->cold);
}

// check_box of both.
Status check_boxes(const Box& a, const Box& b) {
  const Status s = check_box(a);
  return s != Status::Ok ? s : check_box(b);
}

}  // namespace

Status proximity(const Box& a, const Box& b, Proximity& out, Want want) {
  const Status s = check_boxes(a, b);
  if (s != Status::Ok) return out = Proximity{}, s;
  answer(a, b, nullptr, out, want);
  return Status::Ok;
}

Status proximity(const Box& a, const Box& b, ProximityCache& cache, Proximity& out, Want want) {
  const Status s = check_boxes(a, b);
  if (s != Status::Ok) return out = Proximity{}, cache.kind = detail::kCacheBoxBox, cache.active = 0, ++cache.cold, s;
  answer(a, b, &cache, out, want);
  return Status::Ok;
}

void detail::box_answer(const Box& a, const Box& b, ProximityCache* cache, Proximity& out, Want want) {
  answer(a, b, cache, out, want);
}

}  // namespace minksum
