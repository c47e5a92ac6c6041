// Time of impact: where two shapes moving within a tick first touch, by conservative
// advancement (Mirtich, "Impulse-based dynamic simulation of rigid body systems", 1996, 3.3):
// at time t the exact query gives the distance d and the direction n of the closest points;
// along n the two supporting planes close at most at mu = (v_A - v_B) . n + |w_A| r_A +
// |w_B| r_B, so nothing touches before t + g / mu, where g is the gap between them (<= d). A
// pure translation has mu = (v_A - v_B) . n, and each step lands on the supporting plane of
// the feature of A (-) B that the ray of the relative motion meets (van den Bergen's GJK ray
// cast, "Ray casting against general convex objects", 2004): exact to rounding.
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
  Vector3d v;     // the origin's velocity, per tick
  Vector3d axis;  // the rotation's body axis (unit)
  double angle;   // and its angle per tick, in [0, pi]
  Motion(const Isometry3d& a, const Isometry3d& b) : p0(a), v(b.translation() - a.translation()) {
    // (The same rotation at both ends: no turn at all, not the rounding of R0^T R1.)
    const Eigen::AngleAxisd turn(Eigen::Matrix3d(a.linear().transpose() * b.linear()));
    const bool still = a.linear() == b.linear();
    angle = still ? 0.0 : std::abs(turn.angle());
    axis = still ? Vector3d::UnitX() : turn.angle() < 0 ? Vector3d(-turn.axis()) : turn.axis();
  }
  Isometry3d at(double t) const {
    Isometry3d p = Isometry3d::Identity();
    p.linear() = angle > 0 ? Eigen::Matrix3d(p0.linear() * Eigen::AngleAxisd(t * angle, axis).toRotationMatrix())
                           : Eigen::Matrix3d(p0.linear());
    p.translation() = p0.translation() + t * v;
    return p;
  }
};

// The largest |x| of a shape's body vertices: the reach of its rotation about its origin.
double radius(const ConvexShape& s) {
  double r = 0;
  for (const Vector3d& x : s.polytope().vertices) r = std::max(r, x.norm());
  return r;
}

// The gap along n between A's supporting plane and B's: B's lowest vertex minus A's highest.
double gap(const ConvexShape& a, const Isometry3d& pa, const ConvexShape& b, const Isometry3d& pb, const Vector3d& n) {
  double top = -std::numeric_limits<double>::infinity(), bottom = -top;
  const Vector3d na = pa.linear().transpose() * n, nb = pb.linear().transpose() * n;
  for (const Vector3d& x : a.polytope().vertices) top = std::max(top, na.dot(x));
  for (const Vector3d& x : b.polytope().vertices) bottom = std::min(bottom, nb.dot(x));
  return bottom + n.dot(pb.translation()) - top - n.dot(pa.translation());
}

}  // namespace

Status time_of_impact(const ConvexShape& a, const Isometry3d& a0, const Isometry3d& a1, const ConvexShape& b,
                      const Isometry3d& b0, const Isometry3d& b1, TimeOfImpact& out, double tolerance) {
  out = TimeOfImpact{};
  if (a.empty() || b.empty()) return Status::TooFewPoints;
  for (const Isometry3d* pose : {&a0, &a1, &b0, &b1})
    if (const Status s = check_pose(*pose); s != Status::Ok) return s;
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return Status::InvalidArgument;
  const Motion ma(a0, a1), mb(b0, b1);
  const double ra = radius(a), rb = radius(b);
  const bool translation = ma.angle == 0 && mb.angle == 0;
  if (tolerance == 0) {  // the default: 1e-12 of the scene's reach translating, 1e-6 turning
    double reach = 0;
    for (const Isometry3d* pose : {&a0, &a1, &b0, &b1}) reach = std::max(reach, pose->translation().norm());
    tolerance = (translation ? 1e-12 : 1e-6) * (reach + std::max(ra, rb));
  }
  out.tolerance = tolerance;
  const double turning = ma.angle * ra + mb.angle * rb;  // the rotations' share of the closing speed
  double t = 0;
  for (int k = 0; k < kTimeOfImpactIterations; ++k) {
    out.iterations = k + 1;
    const Isometry3d pa = ma.at(t), pb = mb.at(t);
    Proximity p;
    if (const Status s = proximity(a, pa, b, pb, p, Want::Contact); s != Status::Ok) return out = {}, s;
    // The answer at t: the normal is the contact patch's, the one its certificate proved (the
    // witnesses' difference, this close, is mostly rounding).
    // (A patch past its capacity still has its normal.)
    const auto answer = [&] {
      ContactPatch patch;
      const Status s = contact_patch(a, pa, b, pb, tolerance, patch);
      if (s != Status::Ok && s != Status::CapacityExceeded) return out = {}, s;
      out.hit = true, out.time = t, out.normal = patch.normal, out.point_a = p.point_a, out.point_b = p.point_b;
      out.distance = p.distance;
      return Status::Ok;
    };
    // (Overlapping after a step: a touching contact that rounding put inside by its slack.)
    if (p.intersecting || p.distance <= tolerance) return answer();
    // The step from the planes' gap along n, not from d: n is the witnesses' direction, turned
    // by rounding, and the gap along it is what the bound holds for. Near the tolerance that
    // turn can close the gap (faces 1 wide, 1e-11 apart): then the certificate's normal.
    Vector3d n = (p.point_b - p.point_a) / p.distance;
    double g = gap(a, pa, b, pb, n);
    if (!(g > 0)) {
      ContactPatch patch;
      const Status s = contact_patch(a, pa, b, pb, p.distance, patch);
      if (s == Status::Ok || s == Status::CapacityExceeded) n = patch.normal, g = gap(a, pa, b, pb, n);
    }
    if (!(g > 0)) return out.converged = false, out.time = t, Status::Ok;  // rounding stops it here
    const double mu = std::max(0.0, (ma.v - mb.v).dot(n)) + turning;
    if (!(mu > 0)) return Status::Ok;  // they do not close along n: never
    t += g / mu;
    if (!(t <= 1)) return Status::Ok;
  }
  out.converged = false, out.time = t;  // they do not touch before t
  return Status::Ok;
}

}  // namespace minksum
