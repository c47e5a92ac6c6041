// Time of impact of a convex tool against a still mesh. Whatever it turns, the tool stays
// within its radius r of its origin, and the origin moves along a segment: the tool sweeps
// inside that capsule. The octree is walked depth first, nearest first, by the time the
// segment enters each node's box grown by r (a lower bound of when the tool can reach it:
// the grown box holds the capsule's reach), and each triangle by when it enters the
// triangle's bounding sphere grown by r. A face plane of the tool at the start that separates
// a node's box or a triangle by g bounds that time too: no point of the tool moves faster
// than |v| + angle r (Mirtich's bound). A node or triangle that cannot be reached before the
// earliest hit so far is skipped (a tool resting on a surface: all but the few triangles under
// it), and the children are walked soonest first, so the first hit comes early. Each triangle
// left gets time_of_impact's advancement (query/impact.hpp), limited to that earliest hit.
#include <minksum/mesh.hpp>

#include "mesh/mesh_internal.hpp"
#include "query/impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr double kNever = 2;      // an entry time past the tick
constexpr int kSeparatingPlanes = 64;  // the tool's face planes tried as separating planes (the first)

// The tool's face planes at the start (n . x <= o inside), in the mesh's frame.
struct StartPlanes {
  int count = 0;
  Vector3d n[kSeparatingPlanes];
  double o[kSeparatingPlanes];
  StartPlanes(const ConvexPolytope& tool, const Isometry3d& q0) {
    if (tool.flat) return;  // (a flat tool's two faces are its sides: no inside)
    count = int(std::min(tool.faces.size(), size_t(kSeparatingPlanes)));
    for (int f = 0; f < count; ++f) {
      n[f] = q0.linear() * tool.faces[size_t(f)].normal;
      o[f] = tool.faces[size_t(f)].offset + n[f].dot(q0.translation());
    }
  }
  // Whether a face's plane separates the triangle from the tool by more than `limit`. The
  // plane that separated the last triangle is tried first: resting on a surface, one face
  // separates almost every triangle near it.
  bool separates(const Vector3d* t, double limit, int& last) const {
    for (int i = 0; i < count; ++i) {
      const int f = i == 0 ? last : i == last ? 0 : i;
      if (std::min({n[f].dot(t[0]), n[f].dot(t[1]), n[f].dot(t[2])}) - o[f] > limit) return last = f, true;
    }
    return false;
  }
  // A lower bound of the distance from a node's box (centre c, half extents h) to the tool:
  // the largest gap between a face's plane and the box beyond it (0 if none separates).
  double gap(const Vector3d& c, const Vector3d& h) const {
    double best = 0;
    for (int f = 0; f < count; ++f) best = std::max(best, n[f].dot(c) - n[f].cwiseAbs().dot(h) - o[f]);
    return best;
  }
};

// When the segment c0 + s d (s in [0, 1]) first enters the box [lo, hi] (the slab method:
// the latest entry over the axes, unless after the earliest exit); kNever if it does not.
double box_entry(const Vector3d& c0, const Vector3d& d, const Vector3d& lo, const Vector3d& hi) {
  double in = 0, out = 1;
  for (int i = 0; i < 3; ++i) {
    if (d[i] == 0) {
      if (c0[i] < lo[i] || c0[i] > hi[i]) return kNever;
      continue;
    }
    const double s0 = (lo[i] - c0[i]) / d[i], s1 = (hi[i] - c0[i]) / d[i];
    in = std::max(in, std::min(s0, s1)), out = std::min(out, std::max(s0, s1));
    if (in > out) return kNever;
  }
  return in;
}

// When the segment c0 + s d first comes within r of the point c (the smaller root of
// |c0 + s d - c| = r); kNever if it does not in [0, 1].
double sphere_entry(const Vector3d& c0, const Vector3d& d, const Vector3d& c, double r) {
  const Vector3d m = c0 - c;
  const double cc = m.squaredNorm() - r * r;
  if (cc <= 0) return 0;
  const double dd = d.squaredNorm(), md = m.dot(d), disc = md * md - dd * cc;
  if (!(md < 0) || !(disc >= 0)) return kNever;
  const double s = cc / (-md + std::sqrt(disc));  // (the smaller root, without cancellation)
  return s <= 1 ? s : kNever;
}

// A mesh triangle (A, still) and the tool (B): the exact answers the advancement asks for
// where GJK cannot go on. The distance is the nearest of the triangle against the fan
// triangles of the tool's faces (triangle_distance, exact), 0 where they cross or a corner
// lies inside the tool; the normal at the start is the triangle's, towards the tool.
class TriangleAnswers final : public detail::ExactAnswers {
 public:
  TriangleAnswers(const Vector3d* corners, const ConvexShape& tool) : corners_(corners), tool_(tool.polytope()) {}
  bool query(const Isometry3d& pa, const Isometry3d& pb, Proximity& out) const override {
    out = Proximity{};
    const Vector3d t[3] = {pa * corners_[0], pa * corners_[1], pa * corners_[2]};
    double best = std::numeric_limits<double>::infinity();
    for (const auto& face : tool_.faces)
      for (size_t k = 1; k + 1 < face.loop.size(); ++k) {
        const Vector3d s[3] = {pb * tool_.vertices[face.loop[0]], pb * tool_.vertices[face.loop[k]],
                               pb * tool_.vertices[face.loop[k + 1]]};
        Vector3d pt, ps;
        if (const double d = triangle_distance(t, s, pt, ps); d < best) best = d, out.point_a = pt, out.point_b = ps;
      }
    bool inside = !tool_.flat;  // (a flat tool has no inside)
    for (const auto& face : tool_.faces)
      inside = inside && (pb.linear() * face.normal).dot(t[0] - pb.translation()) <= face.offset;
    out.intersecting = inside || best == 0, out.distance = out.intersecting ? 0.0 : best;
    return std::isfinite(best);
  }
  bool normal(const Isometry3d& pa, const Isometry3d& pb, double, Vector3d& out) const override {
    const Vector3d t[3] = {pa * corners_[0], pa * corners_[1], pa * corners_[2]};
    out = detail::unit_normal(t);
    if (out.isZero()) return false;
    if (out.dot(pb.translation() - t[0]) < 0) out = -out;
    return true;
  }

 private:
  const Vector3d* corners_;
  const ConvexPolytope& tool_;
};

}  // namespace

Status time_of_impact(const Octree& a, const Isometry3d& pose_a, const ConvexShape& tool, const Isometry3d& t0,
                      const Isometry3d& t1, TimeOfImpact& out, double tolerance) {
  out = TimeOfImpact{};
  if (a.nodes.empty() || tool.empty()) return Status::TooFewPoints;
  Isometry3d q0, q1;  // the tool's poses in the mesh's frame
  if (const Status s = detail::relative_pose(pose_a, t0, q0); s != Status::Ok) return s;
  if (const Status s = detail::relative_pose(pose_a, t1, q1); s != Status::Ok) return s;
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return Status::InvalidArgument;
  const auto& vertices = tool.polytope().vertices;
  const detail::Mover moving(vertices.data(), int(vertices.size()), q0, q1);
  const Octree::Node& root = a.nodes[0];
  const double reach = std::max(q0.translation().norm(), q1.translation().norm()) + moving.radius +
                       root.box_center.norm() + root.box_half.norm();
  if (tolerance == 0) tolerance = detail::default_tolerance(moving, moving, reach);  // (the mesh is still)
  out.tolerance = tolerance;
  // The capsule's radius, with room for the rounding of the entry times.
  const double r = moving.radius + tolerance + 1e-12 * reach;
  const Vector3d c0 = q0.translation(), d = q1.translation() - q0.translation();
  // No point of the tool moves faster than |d| + angle radius over the tick (Mirtich's bound).
  const double speed = d.norm() + moving.angle * moving.radius, slack = tolerance + 1e-12 * reach;
  // A lower bound of when the tool can come within the tolerance of what lies `gap` beyond one
  // of its face planes at the start.
  const auto plane_time = [&](double gap) { return gap <= slack ? 0.0 : speed > 0 ? (gap - slack) / speed : kNever; };
  const StartPlanes planes(tool.polytope(), q0);
  int last_plane = 0;
  double earliest = 1;  // no hit before it (a hit's time, an unconverged stop's, or the tick's end)
  int iterations = 0;
  struct Entry {
    int node;
    double time;
  };
  Entry stack[8 * 25 + 8];  // depth <= 24 (OctreeOptions): at most 7 more per level
  int top = 0;
  const Vector3d grow = root.box_half + Vector3d::Constant(r);
  stack[top++] = {0, box_entry(c0, d, root.box_center - grow, root.box_center + grow)};
  while (top > 0) {
    const Entry e = stack[--top];
    const Octree::Node& n = a.nodes[e.node];
    if (e.time > earliest) continue;
    if (n.first_child >= 0) {  // the children the tool can reach in time, the soonest on top
      const int from = top;
      for (int c = n.first_child; c < n.first_child + n.child_count; ++c) {
        const Octree::Node& child = a.nodes[c];
        const Vector3d grow = child.box_half + Vector3d::Constant(r);
        const double s = std::max(box_entry(c0, d, child.box_center - grow, child.box_center + grow),
                                  plane_time(planes.gap(child.box_center, child.box_half)));
        if (s <= earliest) stack[top++] = {c, s};
      }
      std::sort(stack + from, stack + top, [](const Entry& x, const Entry& y) { return x.time > y.time; });
      continue;
    }
    for (int x = n.first; x < n.first + n.count; ++x) {
      const int tri = a.items[x];
      const Eigen::Vector4d& sphere = a.spheres[tri];
      if (sphere_entry(c0, d, sphere.head<3>(), sphere[3] + r) > earliest) continue;
      const Vector3d* corners = &a.item_corners[size_t(3) * x];
      if (planes.separates(corners, earliest * speed + slack, last_plane)) continue;
      const detail::Mover still(corners, 3, Isometry3d::Identity(), Isometry3d::Identity());
      TimeOfImpact toi;
      detail::advance(still, moving, tolerance, reach, earliest, TriangleAnswers(corners, tool), toi);
      iterations += toi.iterations;
      // (The earliest hit or unconverged stop; of equal times, the first found.)
      if ((toi.hit || !toi.converged) && (toi.time < earliest || (toi.time == earliest && !out.hit && out.converged)))
        out = toi, out.triangle = tri, earliest = toi.time;
    }
  }
  out.iterations = iterations, out.tolerance = tolerance;
  if (out.hit || !out.converged) {  // back to the world frame
    out.normal = pose_a.linear() * out.normal, out.point_a = pose_a * out.point_a, out.point_b = pose_a * out.point_b;
  }
  return Status::Ok;
}

}  // namespace minksum
