// Time of impact: where two shapes moving within a tick first touch, by conservative
// advancement (Mirtich, "Impulse-based dynamic simulation of rigid body systems", 1996, 3.3):
// at time t the exact query gives the distance d and the direction n of the closest points;
// along n the two supporting planes close at most at mu, so nothing touches before t + g / mu,
// where g is the gap between them (<= d). mu is the directional bound of Zhang, Lee and Kim
// ("Interactive continuous collision detection for non-convex polyhedra", The Visual Computer
// 22, 2006): (v_A - v_B) . n + |w_A x n| r_A + |w_B x n| r_B, with r a shape's reach across
// its rotation axis, not its radius: a point x turning at w moves along n at (w x x) . n =
// x . (n x w), and n x w is square to w. A pure translation has mu = (v_A - v_B) . n, and
// each step lands on the supporting plane of the feature of A (-) B that the ray of the
// relative motion meets (van den Bergen's GJK ray cast, "Ray casting against general convex
// objects", 2004): exact to rounding.
#include <minksum/query.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

// A pose moving from p0 to p1 in a tick: its origin along the segment, its rotation about one
// body axis at a constant rate (|w| = angle per tick).
struct Motion {
  Isometry3d p0;
  Vector3d v;      // the origin's velocity, per tick
  Vector3d axis;   // the rotation's body axis (unit)
  double angle;    // and its angle per tick, in [0, pi]
  Vector3d omega;  // the angular velocity in the world frame (R0 axis angle: fixed as it turns)
  Motion(const Isometry3d& a, const Isometry3d& b) : p0(a), v(b.translation() - a.translation()) {
    // (The same rotation at both ends: no turn at all, not the rounding of R0^T R1.)
    const Eigen::AngleAxisd turn(Eigen::Matrix3d(a.linear().transpose() * b.linear()));
    const bool still = a.linear() == b.linear();
    angle = still ? 0.0 : std::abs(turn.angle());
    axis = still ? Vector3d::UnitX() : turn.angle() < 0 ? Vector3d(-turn.axis()) : turn.axis();
    omega = angle * (a.linear() * axis);
  }
  Isometry3d at(double t) const {
    Isometry3d p = Isometry3d::Identity();
    p.linear() = angle > 0 ? Eigen::Matrix3d(p0.linear() * Eigen::AngleAxisd(t * angle, axis).toRotationMatrix())
                           : Eigen::Matrix3d(p0.linear());
    p.translation() = p0.translation() + t * v;
    return p;
  }
};

// The largest |x| of a shape's body vertices (its reach about its origin), and into `across`
// the largest distance of one from the axis through the origin (its reach across the axis).
double radius(const ConvexShape& s, const Vector3d& axis, double& across) {
  double r2 = 0, across2 = 0;
  for (const Vector3d& x : s.polytope().vertices) {
    const double xx = x.squaredNorm(), along = axis.dot(x);
    r2 = std::max(r2, xx), across2 = std::max(across2, xx - along * along);
  }
  across = std::sqrt(across2) * (1 + 1e-15);  // (rounded up: a bound)
  return std::sqrt(r2);
}

// A shape at pose p moving by m, seen along n: each vertex x has the height h = n . x and
// the rate h' = v . n + (w x r) . n = v . n + r . (n x w) (r: x less the shape's origin); over
// its vertices, the highest (sign 1) or lowest (sign -1) of h + delta h', and that vertex's
// rate into `rate` (of exact ties at delta 0, the one that leads: the line of an actual vertex).
double extreme(const ConvexShape& s, const Isometry3d& p, const Motion& m, const Vector3d& n, double delta,
               double sign, double& rate) {
  const Vector3d nb = p.linear().transpose() * n, wb = p.linear().transpose() * n.cross(m.omega);  // body frame
  const Vector3d k = sign * (nb + delta * wb), ks = sign * wb;
  const auto& vertices = s.polytope().vertices;
  double best = -std::numeric_limits<double>::infinity(), lead = best;
  size_t arg = 0;
  for (size_t i = 0; i < vertices.size(); ++i) {
    const double h = k.dot(vertices[i]);
    if (h < best) continue;
    if (const double r = ks.dot(vertices[i]); h > best || r > lead) best = h, lead = r, arg = i;
  }
  rate = m.v.dot(n) + wb.dot(vertices[arg]);
  return sign * best + n.dot(p.translation()) + delta * m.v.dot(n);
}

// A lower bound of the gap along n between A's supporting plane and B's at t + delta (delta
// 0: the gap itself, B's lowest vertex less A's highest): each vertex moved by its first-order
// motion at t, less what the rotations add beyond it. A point r from the axis turning by phi
// = |w| delta moves off its tangent by |r_perp| |e^(i phi) - 1 - i phi| <= |r_perp| phi^2 / 2,
// and along n by |n x w| / |w| of that: K delta^2 / 2, K = |w| |n x w| r_perp per shape. The
// bound is concave in delta (lowest of lines, less highest of lines, less a parabola). The
// rate of the gap at delta 0+ along the two extreme vertices' lines goes into `slope`.
struct GapBound {
  const ConvexShape &a, &b;
  const Motion &ma, &mb;
  Isometry3d pa, pb;
  Vector3d n;
  double curvature;  // K_A + K_B
  double at(double delta, double* slope = nullptr) const {
    double rate_a, rate_b;
    const double g = extreme(b, pb, mb, n, delta, -1, rate_b) - extreme(a, pa, ma, n, delta, 1, rate_a);
    if (slope) *slope = rate_b - rate_a;
    return g - 0.5 * curvature * delta * delta;
  }
};

}  // namespace

Status time_of_impact(const ConvexShape& a, const Isometry3d& a0, const Isometry3d& a1, const ConvexShape& b,
                      const Isometry3d& b0, const Isometry3d& b1, TimeOfImpact& out, double tolerance) {
  out = TimeOfImpact{};
  if (a.empty() || b.empty()) return Status::TooFewPoints;
  for (const Isometry3d* pose : {&a0, &a1, &b0, &b1})
    if (const Status s = check_pose(*pose); s != Status::Ok) return s;
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return Status::InvalidArgument;
  const Motion ma(a0, a1), mb(b0, b1);
  double across_a, across_b;
  const double ra = radius(a, ma.axis, across_a), rb = radius(b, mb.axis, across_b);
  const bool translation = ma.angle == 0 && mb.angle == 0;
  if (tolerance == 0) {  // the default: 1e-12 of the scene's reach translating, 1e-6 turning
    double reach = 0;
    for (const Isometry3d* pose : {&a0, &a1, &b0, &b1}) reach = std::max(reach, pose->translation().norm());
    tolerance = (translation ? 1e-12 : 1e-6) * (reach + std::max(ra, rb));
  }
  out.tolerance = tolerance;
  // Successive poses are close: each query starts from the last one's features (the answer
  // is the cold one's whatever the cache holds).
  ProximityCache cache;
  Vector3d n = Vector3d::Zero();  // the last step's direction: its planes touch at the answer
  double t = 0;
  for (int k = 0; k < kTimeOfImpactIterations; ++k) {
    out.iterations = k + 1;
    const Isometry3d pa = ma.at(t), pb = mb.at(t);
    Proximity p;
    if (const Status s = proximity(a, pa, b, pb, cache, p, Want::Contact); s != Status::Ok) return out = {}, s;
    // (Overlapping after a step: a touching contact that rounding put inside by its slack.)
    if (p.intersecting || p.distance <= tolerance) {
      out.hit = true, out.time = t, out.distance = p.distance, out.point_a = p.point_a, out.point_b = p.point_b;
      // The normal: the last step's, whose planes the step closed from g > 0 to between 0 and
      // d (a separating plane within the tolerance of both). At the start, the contact
      // patch's, the one its certificate proved (a patch past its capacity still has it).
      if (k > 0) return out.normal = n, Status::Ok;
      ContactPatch patch;
      const Status s = contact_patch(a, pa, b, pb, tolerance, patch);
      if (s != Status::Ok && s != Status::CapacityExceeded) return out = {}, s;
      return out.normal = patch.normal, Status::Ok;
    }
    // The step from the planes' gap along n, not from d: n is the witnesses' direction, turned
    // by rounding, and the gap along it is what the bounds hold for. Near the tolerance that
    // turn can close the gap (faces 1 wide, 1e-11 apart): then the certificate's normal.
    n = (p.point_b - p.point_a) / p.distance;
    GapBound bound{a, b, ma, mb, pa, pb, n, 0};
    double slope;
    double g = bound.at(0, &slope);
    if (!(g > 0)) {
      ContactPatch patch;
      const Status s = contact_patch(a, pa, b, pb, p.distance, patch);
      if (s == Status::Ok || s == Status::CapacityExceeded) n = bound.n = patch.normal, g = bound.at(0, &slope);
    }
    if (!(g > 0)) return out.converged = false, out.time = t, Status::Ok;  // rounding stops it here
    const double turn_a = ma.omega.cross(n).norm() * across_a, turn_b = mb.omega.cross(n).norm() * across_b;
    const double mu = (ma.v - mb.v).dot(n) + turn_a + turn_b;
    // Two certified steps; the longer is taken. Conservative advancement's g / mu, and the
    // bound's own: the parabola q = g + slope delta - K delta^2 / 2 lies above the bound (it
    // follows one vertex of each shape), so at its root the bound is below 0 or the whole
    // step is clear; below 0, the chord from (0, g) meets 0 before the bound does (concave).
    // Near the contact that is a Newton step: the steps shrink quadratically.
    if (!(mu > 0)) return Status::Ok;  // they do not close along n: never
    double step = g / mu;
    if (!translation) {
      bound.curvature = ma.angle * turn_a + mb.angle * turn_b;
      const double root = 2 * g / (-slope + std::sqrt(slope * slope + 2 * bound.curvature * g));
      const double far = std::min(root, 1.5 - t);  // (past the tick's end is far enough)
      const double low = bound.at(far);
      const double sure = low >= 0 ? far : g * far / (g - low);
      step = std::max(step, sure);
    }
    t += step;
    if (!(t <= 1)) return Status::Ok;
  }
  out.converged = false, out.time = t;  // they do not touch before t
  return Status::Ok;
}

}  // namespace minksum
