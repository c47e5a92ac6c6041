// Time of impact: where two shapes moving within a tick first touch, by conservative
// advancement (Mirtich, "Impulse-based dynamic simulation of rigid body systems", 1996, 3.3):
// at time t, a direction n from A towards B and the gap g between the two supporting planes
// along it bound the distance from below; along n the planes close at most at mu, so nothing
// touches before t + g / mu. mu is the directional bound of Zhang, Lee and Kim ("Interactive
// continuous collision detection for non-convex polyhedra", The Visual Computer 22, 2006):
// (v_A - v_B) . n + |w_A x n| r_A + |w_B x n| r_B, with r a shape's reach across its rotation
// axis, not its radius: a point x turning at w moves along n at (w x x) . n = x . (n x w), and
// n x w is square to w. The directions are GJK's on A (-) B, its simplex kept from one step to
// the next, and GJK's nearest points (a point of each shape) bound the distance from above and
// stop it: van den Bergen's GJK ray cast ("Ray casting against general convex objects with
// application to continuous collision detection", 2004), where a pure translation's steps land
// on the supporting plane the ray of the relative motion meets: exact to the tolerance.
#include "query/impact.hpp"
#include "query/wide_scan.hpp"

#include "core/scale.hpp"
#include "geometry/closest.hpp"
#include "query/rounded.hpp"
#include "shape/shape_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace detail {

Mover::Mover(const Vector3d* vertices, int size, const Isometry3d& a, const Isometry3d& b)
    : vertices(vertices), size(size), p0(a), v(b.translation() - a.translation()) {
  if (a.linear() != b.linear()) {  // (the same rotation at both ends: no turn, not the rounding of R0^T R1)
    const Eigen::AngleAxisd turn(Eigen::Matrix3d(a.linear().transpose() * b.linear()));
    angle = std::abs(turn.angle()), axis = turn.angle() < 0 ? Vector3d(-turn.axis()) : turn.axis();
    omega = angle * (a.linear() * axis);
  }
  double r2 = 0, across2 = 0;
  if (angle == 0) {  // (no turn: nothing moves across an axis)
    for (int i = 0; i < size; ++i) r2 = std::max(r2, vertices[i].squaredNorm());
  } else {
    for (int i = 0; i < size; ++i) {
      const double xx = vertices[i].squaredNorm(), along = axis.dot(vertices[i]);
      r2 = std::max(r2, xx), across2 = std::max(across2, xx - along * along);
    }
  }
  radius = std::sqrt(r2), across = std::sqrt(across2) * (1 + 1e-15);  // (rounded up: a bound)
}

Mover::Mover(const ConvexShape& shape, const Isometry3d& p0, const Isometry3d& p1)
    : Mover(shape.polytope().vertices.data(), int(shape.polytope().vertices.size()), p0, p1) {
  const ShapeData& d = *ShapeAccess::data(shape);
  x = d.px.data(), y = d.py.data(), z = d.pz.data();
}

Isometry3d Mover::at(double t) const {
  Isometry3d p = p0;
  if (angle > 0) p.linear() = p0.linear() * Eigen::AngleAxisd(t * angle, axis).toRotationMatrix();
  p.translation() += t * v;
  return p;
}

}  // namespace detail

Isometry3d Motion::at(double t) const { return detail::Mover(nullptr, 0, from, to).at(t); }

namespace {

using detail::Mover;

// A body at pose p moving by m, seen along n: each vertex x has the height h = n . x and the
// rate h' = v . n + (w x r) . n = v . n + r . (n x w) (r: x less the body's origin); over its
// vertices, the highest (sign 1) or lowest (sign -1) of h + delta h', and that vertex's rate
// into `rate` and index into `arg` (of exact ties at delta 0, the one that leads: the line of
// an actual vertex).
double extreme(const Mover& m, const Isometry3d& p, const Vector3d& n, double delta, double sign, double& rate,
               int& arg) {
  const Vector3d nb = p.linear().transpose() * n;  // body frame
  double best = -std::numeric_limits<double>::infinity();
  arg = 0;
  if (m.angle == 0) {  // (no turn: every vertex's rate is v . n; the first highest)
    const Vector3d k = sign * nb;
    if (m.x && m.size >= detail::kWideScan) {  // (a large translating body: the SIMD kernel)
      detail::wide_scan(m.x, m.y, m.z, m.size, k.x(), k.y(), k.z(), best, arg);
    } else {
      for (int i = 0; i < m.size; ++i)
        if (const double h = k.dot(m.vertices[i]); h > best) best = h, arg = i;
    }
    rate = m.v.dot(n);
    return sign * best + n.dot(p.translation()) + delta * rate;
  }
  const Vector3d wb = p.linear().transpose() * n.cross(m.omega);
  const Vector3d k = sign * (nb + delta * wb), ks = sign * wb;
  double lead = best;
  for (int i = 0; i < m.size; ++i) {
    const double h = k.dot(m.vertices[i]);
    if (h < best) continue;
    if (const double r = ks.dot(m.vertices[i]); h > best || r > lead) best = h, lead = r, arg = i;
  }
  rate = m.v.dot(n) + wb.dot(m.vertices[arg]);
  return sign * best + n.dot(p.translation()) + delta * m.v.dot(n);
}

// A lower bound of the gap along n between A's supporting plane and B's at t + delta (delta
// 0: the gap itself, B's lowest vertex less A's highest): each vertex moved by its first-order
// motion at t, less what the rotations add beyond it. A point r from the axis turning by phi
// = |w| delta moves off its tangent by |r_perp| |e^(i phi) - 1 - i phi| <= |r_perp| phi^2 / 2,
// and along n by |n x w| / |w| of that: K delta^2 / 2, K = |w| |n x w| r_perp per body. The
// bound is concave in delta (lowest of lines, less highest of lines, less a parabola). The
// rate of the gap at delta 0+ along the two extreme vertices' lines goes into `slope`, and
// those vertices (M's support point along -n) into `support`.
struct GapBound {
  const Mover &a, &b;
  const Isometry3d &pa, &pb;
  Vector3d n;
  double curvature;  // K_A + K_B
  double at(double delta, double* slope = nullptr, int* support = nullptr) const {
    double rate_a, rate_b;
    int ia, ib;
    const double g = extreme(b, pb, n, delta, -1, rate_b, ib) - extreme(a, pa, n, delta, 1, rate_a, ia);
    if (slope) *slope = rate_b - rate_a;
    if (support) support[0] = ia, support[1] = ib;
    return g - 0.5 * curvature * delta * delta;
  }
};

// GJK's simplex on M = A (-) B (detail::PairSimplex, as the proximity query's GJK keeps it),
// kept from one step to the next and re-evaluated at each step's poses, as van den Bergen's ray
// cast keeps it along the ray.
struct Simplex : detail::PairSimplex {
  Simplex() { n = 1; }
  // Its point nearest the origin at the poses: a* - b* (scaled by k), with a* on A and b* on
  // B into near_a and near_b; the simplex keeps the pairs that span it. False if the origin
  // is inside (they overlap, to rounding) or the simplex is empty.
  bool nearest(const Mover& a, const Isometry3d& pa, const Mover& b, const Isometry3d& pb, double k, Vector3d& near_a,
               Vector3d& near_b) {
    if (n == 0) return false;
    Vector3d xa[4], xb[4];
    for (int j = 0; j < n; ++j)
      xa[j] = pa * a.vertices[ia[j]], xb[j] = pb * b.vertices[ib[j]], w[j] = k * (xa[j] - xb[j]);
    int kept[4];
    const int m = reduce(kept);
    if (m == 0) n = 0;
    if (m <= 0) return false;
    near_a.setZero(), near_b.setZero();
    for (int j = 0; j < m; ++j) near_a += l[j] * xa[kept[j]], near_b += l[j] * xb[kept[j]];
    return true;
  }
  // Adds a support pair (its point comes with the next poses); false if it is there already
  // or the simplex is full (GJK cannot go on).
  bool add(const int (&pair)[2]) {
    if (holds(pair[0], pair[1]) || n == 4) return false;
    PairSimplex::add(pair[0], pair[1], Vector3d::Zero());
    return true;
  }
};

// The step a gap g > tolerance / 2 along the bound's direction certifies (see the top):
// conservative advancement's g / mu and the bound's own, the longer; each closes the gap to
// half the tolerance, never further. That is the band's contract (TimeOfImpact): over every
// step the shapes stay at least tolerance / 2 apart, so a pass closer than that is never
// stepped over; and the next query is well apart by rounding's measure (touching is where an
// exact query's certificates fail and it searches). 0: they never close along it.
double certified_step(GapBound& bound, double g, double slope, double tolerance, double radii, double t) {
  const Mover &a = bound.a, &b = bound.b;
  const double turn_a = a.omega.cross(bound.n).norm() * a.across, turn_b = b.omega.cross(bound.n).norm() * b.across;
  const double mu = (a.v - b.v).dot(bound.n) + turn_a + turn_b;
  if (!(mu > 0)) return 0;
  const double aim = 0.5 * tolerance + radii, closable = g - aim;
  const double step = closable / mu;
  if (a.angle == 0 && b.angle == 0) return step;
  // The parabola g + slope delta - K delta^2 / 2 lies above the bound (it follows one vertex
  // of each body), so at its root the bound is below 0 or the whole step is clear; below 0,
  // the chord from (0, g) meets 0 before the bound does (concave). Near the contact that is a
  // Newton step: the steps shrink quadratically.
  bound.curvature = a.angle * turn_a + b.angle * turn_b;
  const double root = 2 * closable / (-slope + std::sqrt(slope * slope + 2 * bound.curvature * closable));
  const double far = std::min(root, 1.5 - t);  // (past the tick's end is far enough)
  const double low = bound.at(far) - aim;
  return std::max(step, low >= 0 ? far : closable * far / (closable - low));
}

}  // namespace

namespace detail {

Status advance(const Mover& a, const Mover& b, double tolerance, double reach, double limit, const ExactAnswers& exact,
               double radii, TimeOfImpact& out) {
  out = TimeOfImpact{};
  out.tolerance = tolerance;
  const double k = scale_to_one(reach);  // (GJK's squared lengths neither over- nor underflow)
  Simplex simplex;
  // GJK starts from the features that lead along the relative motion: A's highest towards B's
  // approach and B's highest along it (a guess that a head-on sweep's contact confirms).
  if (const Vector3d toward = b.v - a.v; toward.squaredNorm() > 0) {
    double unused;
    extreme(a, a.p0, -toward, 0, 1, unused, simplex.ia[0]);
    extreme(b, b.p0, toward, 0, 1, unused, simplex.ib[0]);
  }
  Vector3d n = Vector3d::Zero();  // the last step's direction: its planes touch at the answer
  double t = 0, previous = std::numeric_limits<double>::infinity();  // GJK's last |b* - a*| since a step
  for (int iteration = 0; iteration < kTimeOfImpactIterations; ++iteration) {
    out.iterations = iteration + 1;
    const Isometry3d pa = a.at(t), pb = b.at(t);
    // Each iteration has a pair of points (a* on A, b* on B: |b* - a*| bounds the distance
    // from above) and a direction whose supporting planes bound it from below (the gap g):
    // GJK's, or the exact query's where GJK cannot go on (the origin inside its simplex, or
    // no progress: rounding or an overlap) and at the start where g shows a gap too small to
    // tell touching from apart (there the query alone does, as proximity answers it).
    Vector3d near_a, near_b;
    GapBound bound{a, b, pa, pb, Vector3d::Zero(), 0};
    double apart = 0, g = 0, slope = 0;
    int support[2] = {};
    bool gjk = simplex.nearest(a, pa, b, pb, k, near_a, near_b) && (apart = (near_b - near_a).norm()) < previous;
    if (gjk && apart - radii > tolerance) {
      bound.n = (near_b - near_a) / apart, g = bound.at(0, &slope, support);
      gjk = t > 0 || !(g - radii > 0) || g - radii > 1e-12 * reach;  // (no gap: GJK goes on, no step is taken)
    }
    if (!gjk) {
      Proximity p;
      if (!exact.query(pa, pb, p)) return out.converged = false, out.time = t, Status::Ok;
      near_a = p.point_a, near_b = p.point_b, apart = p.intersecting ? 0.0 : p.distance;
      if (apart - radii > tolerance) {
        // The witnesses' direction, turned by rounding, can close the gap near the tolerance
        // (faces 1 wide, 1e-11 apart): then the certificate's normal. Where neither shows a
        // gap (the nearest features an edge's end, 1e-11 apart, turned by 1e-6 by rounding),
        // the distance itself: no point moves faster than |v| + |w| r, whatever the
        // direction (Mirtich's bound).
        // (Unit by its own length: the query's distance and its rounded witnesses' differ, by
        // 1e-9 of it at 4e-10 apart.)
        bound.n = (near_b - near_a).normalized(), g = bound.at(0, &slope, support);
        if (!(g - radii > 0.5 * tolerance) && exact.normal(pa, pb, apart, near_a, near_b, bound.n))
          g = bound.at(0, &slope, support);
        if (!(g - radii > 0.5 * tolerance)) {
          const double mu = (a.v - b.v).norm() + a.omega.norm() * a.radius + b.omega.norm() * b.radius;
          if (!(mu > 0)) return Status::Ok;  // still: they stay apart
          const double gap = apart - radii;
          t += (gap - (gap > 2 * tolerance ? tolerance : 0.5 * gap)) / mu, n.setZero();  // (gap/2 > tol/2)
          if (!(t <= limit)) return Status::Ok;
          simplex.n = 0;  // (the exact query again next)
          continue;
        }
      }
    }
    if (!(apart - radii > tolerance)) {
      out.hit = true, out.time = t, out.distance = std::max(0.0, apart - radii), out.point_a = near_a, out.point_b = near_b;
      // The normal: the last step's, whose planes the step closed from g > 0 to between 0 and
      // the distance (a separating plane within the tolerance of both); at the start or
      // after a step by the distance alone, the certified one of the contact.
      if (t > 0 && !n.isZero()) return out.normal = n, Status::Ok;
      if (!exact.normal(pa, pb, tolerance + radii, near_a, near_b, out.normal))
        out.normal = apart > 0 ? Vector3d((near_b - near_a).normalized()) : Vector3d::UnitZ();  // (none better known)
      return Status::Ok;
    }
    const bool added = simplex.add(support);  // GJK's next support point: M's along -v
    // No step where the gap is within half the tolerance (a step would close it past the
    // band's contract): GJK goes on at these poses (stalled: the exact query next).
    if (!(g - radii > 0.5 * tolerance)) {
      if (!added) simplex.n = 0;
      previous = apart;
      continue;
    }
    const double step = certified_step(bound, g, slope, tolerance, radii, t);
    if (!(step > 0)) return Status::Ok;  // they never close along it: no hit
    n = bound.n, t += step, previous = std::numeric_limits<double>::infinity();
    if (!(t <= limit)) return Status::Ok;
  }
  out.converged = false, out.time = t;  // they do not touch before t
  return Status::Ok;
}

}  // namespace detail

namespace {

// A prepared pair's exact answers on its cores (the radii left out: the advancement adds
// them): the exact query, and the contact patch's normal.
class ShapeAnswers final : public detail::ExactAnswers {
 public:
  ShapeAnswers(const ConvexShape& a, const ConvexShape& b) : a_(a), b_(b) {}
  bool query(const Isometry3d& pa, const Isometry3d& pb, Proximity& out) const override {
    if (check_pose(pa) != Status::Ok || check_pose(pb) != Status::Ok) return false;
    detail::cores_proximity(a_, pa, b_, pb, out);
    return true;
  }
  bool normal(const Isometry3d& pa, const Isometry3d& pb, double margin, const Vector3d&, const Vector3d&,
              Vector3d& out) const override {
    ContactPatch patch;  // (a patch past its capacity still has its normal)
    if (check_pose(pa) != Status::Ok || check_pose(pb) != Status::Ok) return false;
    const Status s = detail::cores_patch(a_, pa, b_, pb, margin, patch);
    if (s != Status::Ok && s != Status::CapacityExceeded) return false;
    return out = patch.normal, true;
  }

 private:
  const ConvexShape &a_, &b_;
};

}  // namespace

Status time_of_impact(const ConvexShape& a, const Isometry3d& a0, const Isometry3d& a1, const ConvexShape& b,
                      const Isometry3d& b0, const Isometry3d& b1, TimeOfImpact& out, double tolerance) {
  out = TimeOfImpact{};
  if (a.empty() || b.empty()) return Status::TooFewPoints;
  const Isometry3d* poses[4] = {&a0, &a1, &b0, &b1};
  for (int k = 0; k < 4; ++k) {
    // (A still shape's end pose is its start pose, checked: by position, not address, for one
    // object passed as both poses is a still shape too, and was left unchecked.)
    if (k % 2 == 1 && poses[k]->matrix() == poses[k - 1]->matrix()) continue;
    if (const Status s = check_pose(*poses[k]); s != Status::Ok) return s;
  }
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return Status::InvalidArgument;
  // The cores advance until they come within the radii (plus the tolerance) of each other; the
  // witnesses then move out to the surfaces along the normal.
  const double radii = a.radius() + b.radius();
  const Mover ma(a, a0, a1), mb(b, b0, b1);
  double reach = 0;
  for (const Isometry3d* pose : {&a0, &a1, &b0, &b1}) reach = std::max(reach, pose->translation().norm());
  reach += std::max(ma.radius, mb.radius) + radii;
  if (tolerance == 0) tolerance = detail::default_tolerance(ma, mb, reach);
  const Status s = detail::advance(ma, mb, tolerance, reach, 1, ShapeAnswers(a, b), radii, out);
  if (out.hit) out.point_a += a.radius() * out.normal, out.point_b -= b.radius() * out.normal;
  return s;
}

}  // namespace minksum
