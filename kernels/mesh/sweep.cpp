// Time of impact of a convex tool against a still mesh, by branch and bound on lower bounds of
// when the tool can first reach a node's box or a triangle:
// - Whatever it turns, the tool stays within its radius r of its origin, and the origin moves
//   along a segment: the tool sweeps inside that capsule, which enters each node's box grown
//   by r, and each triangle's bounding sphere grown by r, no sooner than the slab or sphere
//   entry time says.
// - A face plane of the tool at the start, or the triangle's own plane, that separates them by
//   g: no point of the tool advances along the plane's normal n faster than d . n + |n x w| r
//   (d: the origin's displacement, w: the turn; the directional bound of Zhang, Lee and Kim, as
//   in query/impact.cpp).
// The octree is walked depth first, the soonest child on top; the triangles in reach wait in
// a heap and get time_of_impact's advancement (query/impact.hpp) soonest first, before any
// node that may be reached later. Whatever cannot be reached before the earliest hit so far
// is skipped: a tool sliding on a surface advances against the few triangles under it. So is
// a triangle that the same planes taken at the hit's pose, bounded backwards in time, prove
// apart until the hit: the many ties under a face resting on a face.
#include <minksum/kernels.hpp>
#include <minksum/mesh.hpp>

#include "mesh/mesh_internal.hpp"
#include "query/impact.hpp"
#include "shape/shape_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Isometry3d;
using Eigen::Vector3d;

namespace {

constexpr double kNever = 2;      // an entry time past the tick
constexpr int kSeparatingPlanes = 64;  // the tool's face planes tried as separating planes (the first)
constexpr int kHeapTriangles = 256;    // triangles in reach waiting for their advancement

// The tool's face planes at one pose of the tick (n . x <= o inside), in the mesh's frame, its
// vertices there (if no more than kSeparatingPlanes), and how fast each plane can move: over
// the tick a point of the tool moves along n by d . n (d: the origin's displacement) give or
// take |n x w| r (w: the turn's vector, angle times unit axis; r: the farthest vertex from the
// axis: the turn moves a point square to the axis, by at most its arc).
// - Forward, from the start: what lies beyond a plane by g is out of reach before g over
//   (d . n + |n x w| r).
// - Backward, from the pose at the earliest hit e: what lies beyond a plane there by g was
//   beyond it at every earlier time if g > e max(0, |n x w| r - d . n), and cannot make the hit
//   late. This settles a face resting on a face: the triangles under it share the start's gap,
//   and the turn's term leaves their forward bounds short of the hit, but the tool was above
//   their plane all along.
struct ToolPlanes {
  int count = 0, corners = 0;
  Vector3d n[kSeparatingPlanes], v[kSeparatingPlanes];
  double o[kSeparatingPlanes], ahead[kSeparatingPlanes], behind[kSeparatingPlanes];
  Vector3d d, w;
  double r = 0, slack = 0;  // slack: gaps within it count as none
  ToolPlanes() = default;
  ToolPlanes(const ConvexPolytope& tool, const detail::Rigid& q, const Vector3d& d, const Vector3d& w, double r,
             double slack)
      : d(d), w(w), r(r), slack(slack) {
    if (tool.vertices.size() <= size_t(kSeparatingPlanes)) {
      corners = int(tool.vertices.size());
      for (int i = 0; i < corners; ++i) v[i] = q.point(tool.vertices[size_t(i)]);
    }
    if (tool.flat) return;  // (a flat tool's two faces are its sides: no inside)
    count = int(std::min(tool.faces.size(), size_t(kSeparatingPlanes)));
    for (int f = 0; f < count; ++f) {
      q.plane(tool.faces[size_t(f)].normal, tool.faces[size_t(f)].offset, n[f], o[f]);
      const double turn = n[f].cross(w).norm() * r;
      ahead[f] = n[f].dot(d) + turn, behind[f] = turn - n[f].dot(d);
    }
  }
  // The triangle's gap beyond face f (less the slack).
  double gap(int f, const Vector3d* t) const {
    return std::min({n[f].dot(t[0]), n[f].dot(t[1]), n[f].dot(t[2])}) - o[f] - slack;
  }
  // The triangle's own plane (unit normal m) and the tool's vertices' gap to it, g > 0 where
  // they all lie on one side; m is turned towards them. False if unknown.
  bool own_plane(const Vector3d* t, Vector3d& m, double& g) const {
    m = (t[1] - t[0]).cross(t[2] - t[0]);
    const double length = m.norm();
    if (corners == 0 || !(length > 0)) return false;
    m /= length;
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int i = 0; i < corners; ++i) {
      const double h = m.dot(v[i] - t[0]);
      lo = std::min(lo, h), hi = std::max(hi, h);
    }
    if (lo < -hi) m = -m, lo = -hi;
    g = lo - slack;
    return true;
  }
  // Forward: whether a face's plane keeps the triangle out of reach until after `limit`. The
  // plane that did so for the last triangle is tried first: resting on a surface, one face
  // separates almost every triangle near it.
  bool out_of_reach(const Vector3d* t, double limit, int& last) const {
    for (int i = 0; i < count; ++i) {
      const int f = i == 0 ? last : i == last ? 0 : i;
      const double g = gap(f, t);
      if (g > 0 && g > limit * ahead[f]) return last = f, true;
    }
    return false;
  }
  // Forward: a lower bound of when the tool can reach the triangle (0 if none is known), by
  // the face planes and by its own plane (the tool approaching it at most at
  // |m x w| r - d . m); past the tick, kNever.
  double reach_time(const Vector3d* t) const {
    double best = 0;
    const auto bound = [&](double g, double rate) { best = std::max(best, g > rate ? kNever : g / rate); };
    for (int f = 0; f < count; ++f)
      if (const double g = gap(f, t); g > 0) bound(g, ahead[f]);
    Vector3d m;
    double g;
    if (own_plane(t, m, g) && g > 0) bound(g, m.cross(w).norm() * r - m.dot(d));
    return best;
  }
  // Forward: the same for a node's box (centre c, half extents h), by the face planes.
  double reach_time(const Vector3d& c, const Vector3d& h) const {
    double best = 0;
    for (int f = 0; f < count; ++f) {
      const double g = n[f].dot(c) - n[f].cwiseAbs().dot(h) - o[f] - slack;
      if (g > 0) best = std::max(best, g > ahead[f] ? kNever : g / ahead[f]);
    }
    return best;
  }
  // Backward, with these planes at the pose of time e: whether the triangle was apart from the
  // tool at every time in [0, e].
  bool apart_until(const Vector3d* t, double e) const {
    for (int f = 0; f < count; ++f)
      if (const double g = gap(f, t); g > 0 && g > e * std::max(0.0, behind[f])) return true;
    Vector3d m;
    double g;
    return own_plane(t, m, g) && g > 0 && g > e * std::max(0.0, m.cross(w).norm() * r + m.dot(d));
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
// |c0 + s d - c| = r); kNever if it does not in [0, 1]. Along the unit direction u = d / |d|,
// so that no product of two squared lengths is formed: |d|^2 (|m|^2 - r^2) overflows past
// coordinates of 1e77, where the README accepts 1e100 (a NaN discriminant culled every
// triangle: fuzz_query-mesh-toi-disagrees).
double sphere_entry(const Vector3d& c0, const Vector3d& d, const Vector3d& c, double r) {
  const Vector3d m = c0 - c;
  const double cc = m.squaredNorm() - r * r;
  if (cc <= 0) return 0;
  const double length = d.norm();
  if (!(length > 0)) return kNever;
  const double mu = m.dot(d) / length, disc = mu * mu - cc;
  if (!(mu < 0) || !(disc >= 0)) return kNever;
  const double s = cc / (-mu + std::sqrt(disc)) / length;  // (the smaller root, without cancellation)
  return s <= 1 ? s : kNever;
}

// A point or segment core (no face planes): its exact distance at the start, to a node's box, a
// triangle's sphere or the triangle, bounds when it can come within the radius, since no point
// of it moves faster than `speed` = |d| + angle |x| (Mirtich's bound); and its distance at the
// hit bounds it backwards. Gaps within `slack` (the tolerance and rounding) count as none. Kept
// out of line: the polytope tools' walk does not carry it.
class LineCore {
 public:
  const bool on;  // the tool's core is a point or a segment
  LineCore(const ConvexShape& tool, const detail::Rigid& q0, double speed, double radius, double slack)
      : on(!detail::ShapeAccess::data(tool)->has_faces()), core_(tool.polytope()), speed_(speed), radius_(radius),
        slack_(slack), start_{q0.point(core_.vertices.front()), q0.point(core_.vertices.back())} {}
  // When the core may first come within reach of a node's box (centre c, half extents h).
  [[gnu::noinline]] double box_entry(const Vector3d& c, const Vector3d& h) const {
    return entry(start_.box_gap(c, h) - radius_ - slack_);
  }
  // And of a triangle (its bounding sphere first), unless that is after `limit` anyway.
  [[gnu::noinline]] double triangle_entry(const Vector3d* t, const Eigen::Vector4d& sphere, double limit) const {
    const Vector3d c = sphere.head<3>();
    const double s = entry((c - start_.nearest(c)).norm() - sphere[3] - radius_ - slack_);
    return s > limit ? s : std::max(s, entry(gap(t, start_) - slack_));
  }
  // Whether the triangle, beyond `margin` at the hit (time e), was out of reach before it.
  [[gnu::noinline]] bool apart_until(const Vector3d* t, const detail::Rigid& hit, double e, double margin) const {
    return gap(t, {hit.point(core_.vertices.front()), hit.point(core_.vertices.back())}) - margin > e * speed_;
  }

 private:
  double entry(double g) const { return !(g > 0) ? 0.0 : g >= speed_ ? kNever : g / speed_; }
  // The core's distance to the triangle, less the radius (the core as a flat triangle).
  double gap(const Vector3d* t, const detail::PlacedSegment& s) const {
    const Vector3d c[3] = {s.s0, s.s1, s.s1}, u[3] = {t[0], t[1], t[2]};
    Vector3d p0, p1;
    return triangle_distance(u, c, p0, p1) - radius_;
  }
  const ConvexPolytope& core_;
  const double speed_, radius_, slack_;
  const detail::PlacedSegment start_;
};

// A mesh triangle (A, still) and the tool's core (B): the exact answers the advancement asks
// for where GJK cannot go on. The distance is the nearest of the triangle against the fan
// triangles of the core's faces (a point or segment core: itself as a flat triangle;
// triangle_distance, exact), 0 where they cross or a corner lies inside a solid core. The
// normal at a contact is the separating axis whose planes lie farthest apart (section 4 of
// Gottschalk, Lin and Manocha's OBBTree, 1996: the triangle's normal, the core's face normals,
// the crosses of their edges, and the nearest points' direction), the tool on its side: a
// separating plane, or at an overlap the least push apart along those axes.
// (The triangle's normal alone is no such plane where the tool meets an edge of it from the
// side: a haptic proxy backed off along it went into the scene.)
class TriangleAnswers final : public detail::ExactAnswers {
 public:
  TriangleAnswers(const Vector3d* corners, const ConvexShape& tool) : corners_(corners), tool_(tool.polytope()) {}
  bool query(const Isometry3d& pa, const Isometry3d& pb, Proximity& out) const override {
    out = Proximity{};
    const detail::Rigid A(pa), B(pb);
    const Vector3d t[3] = {A.point(corners_[0]), A.point(corners_[1]), A.point(corners_[2])};
    double best = std::numeric_limits<double>::infinity();
    const auto consider = [&](const Vector3d (&s)[3]) {
      Vector3d pt, ps;
      if (const double d = triangle_distance(t, s, pt, ps); d < best) best = d, out.point_a = pt, out.point_b = ps;
    };
    for (const auto& face : tool_.faces)
      for (size_t k = 1; k + 1 < face.loop.size(); ++k)
        consider({B.point(tool_.vertices[face.loop[0]]), B.point(tool_.vertices[face.loop[k]]),
                  B.point(tool_.vertices[face.loop[k + 1]])});
    if (tool_.faces.empty())
      consider({B.point(tool_.vertices.front()), B.point(tool_.vertices.back()), B.point(tool_.vertices.back())});
    bool inside = !tool_.flat && !tool_.faces.empty();  // (a flat tool, a point or a segment has no inside)
    const Vector3d corner = B.body_point(t[0]);  // (the tool's planes as stored)
    for (const auto& face : tool_.faces) inside = inside && face.normal.dot(corner) <= face.offset;
    out.intersecting = inside || best == 0, out.distance = out.intersecting ? 0.0 : best;
    return std::isfinite(best);
  }
  bool normal(const Isometry3d& pa, const Isometry3d& pb, double, const Vector3d& near_a, const Vector3d& near_b,
              Vector3d& out) const override {
    // In the tool's frame, where its vertices, faces and edges are as stored: the triangle is
    // placed there once, and the axis found is turned back.
    const detail::Rigid A(pa), B(pb);
    Vector3d t[3];
    for (int k = 0; k < 3; ++k) t[k] = B.body_point(A.point(corners_[k]));
    double best = -std::numeric_limits<double>::infinity();
    Vector3d axis = Vector3d::Zero();
    // The gap between the planes along axis c (either sign), the tool on the far side.
    const auto consider = [&](const Vector3d& c) {
      const double length = c.norm();
      if (!(length > 0) || !std::isfinite(length)) return;
      const Vector3d u = c / length;
      double lo_t = std::numeric_limits<double>::infinity(), hi_t = -lo_t, lo_b = lo_t, hi_b = -lo_t;
      for (const Vector3d& x : t) lo_t = std::min(lo_t, u.dot(x)), hi_t = std::max(hi_t, u.dot(x));
      for (const Vector3d& v : tool_.vertices) lo_b = std::min(lo_b, u.dot(v)), hi_b = std::max(hi_b, u.dot(v));
      if (lo_b - hi_t > best) best = lo_b - hi_t, axis = u;
      if (lo_t - hi_b > best) best = lo_t - hi_b, axis = -u;
    };
    // The nearest points' direction and the triangle's normal first: where one of them separates
    // (it mostly does), the crosses of the edges are not needed (the sweep asks at every step
    // whose gap the rounding closed).
    const Vector3d edge[3] = {t[1] - t[0], t[2] - t[1], t[0] - t[2]};
    consider(B.to_body(near_b - near_a));
    consider(edge[0].cross(edge[1]));
    if (!(best >= 0)) {
      for (const auto& face : tool_.faces) consider(face.normal);
      const auto crosses = [&](const Vector3d& e) {
        for (const Vector3d& f : edge) consider(e.cross(f));
      };
      for (size_t k = 0; k < tool_.edges.size() && !(best >= 0); ++k)
        crosses(tool_.vertices[size_t(tool_.edges[k].v1)] - tool_.vertices[size_t(tool_.edges[k].v0)]);
      if (tool_.edges.empty() && tool_.vertices.size() == 2) crosses(tool_.vertices[1] - tool_.vertices[0]);
    }
    out = B.turn(axis);
    return best > -std::numeric_limits<double>::infinity();
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
  detail::Rigid q0, q1;  // the tool's poses in the mesh's frame
  if (const Status s = detail::relative_pose(pose_a, t0, q0); s != Status::Ok) return s;
  if (const Status s = detail::relative_pose(pose_a, t1, q1); s != Status::Ok) return s;
  if (!(tolerance >= 0) || !std::isfinite(tolerance)) return Status::InvalidArgument;
  const detail::Mover moving(tool, q0.isometry(), q1.isometry());
  const Octree::Node& root = a.nodes[0];
  // A rounded tool: its core advances until it comes within the radius of a triangle, and its
  // face planes and vertices keep triangles out of reach beyond the radius.
  const double radius = tool.radius();
  const double reach = std::max(q0.t.norm(), q1.t.norm()) + moving.radius + radius +
                       root.box_center.norm() + root.box_half.norm();
  if (tolerance == 0) tolerance = detail::default_tolerance(moving, moving, reach);  // (the mesh is still)
  out.tolerance = tolerance;
  // The capsule's radius, with room for the rounding of the entry times.
  const double r = moving.radius + radius + tolerance + 1e-12 * reach;
  const Vector3d c0 = q0.t, d = q1.t - q0.t;
  // Forward from the start, gaps within the tolerance count as none (a hit is coming within
  // it); backward from the earliest hit, those within half of it, less rounding (no pass that
  // close before it).
  const ToolPlanes planes(tool.polytope(), q0, d, moving.omega, moving.across, radius + tolerance + 1e-12 * reach);
  ToolPlanes at_hit;
  // A point or segment core has no planes: its distances bound when it can come within reach.
  const LineCore line(tool, q0, d.norm() + moving.angle * moving.radius, radius, tolerance + 1e-12 * reach);
  detail::Rigid hit_pose = q0;
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
  // The triangles in reach wait in a heap, soonest first; before a node is opened, those that
  // may be reached before it get their advancement (best first: the earliest hit comes early,
  // and bounds what is left). A full heap advances its soonest to make room.
  Entry heap[kHeapTriangles];
  int waiting = 0;
  const auto later = [](const Entry& x, const Entry& y) { return x.time > y.time; };
  // A hit at the start: none can come sooner, so the walk ends (a tool that starts in contact
  // pays for the triangles it met first, not for every one it covers).
  const auto settled = [&] { return out.hit && earliest <= 0; };
  const auto advance_next = [&] {
    std::pop_heap(heap, heap + waiting, later);
    const Entry c = heap[--waiting];
    if (c.time > earliest || settled()) return;
    const Vector3d* corners = &a.item_corners[size_t(3) * c.node];
    if (out.hit && at_hit.apart_until(corners, earliest)) return;
    if (out.hit && line.on && line.apart_until(corners, hit_pose, earliest, 0.5 * tolerance - 1e-12 * reach)) return;
    const detail::Mover still(corners, 3, Isometry3d::Identity(), Isometry3d::Identity());
    TimeOfImpact toi;
    detail::advance(still, moving, tolerance, reach, earliest, TriangleAnswers(corners, tool), radius, toi);
    iterations += toi.iterations;
    // (The earliest hit or unconverged stop; of equal times, the first found.)
    if ((toi.hit || !toi.converged) && (toi.time < earliest || (toi.time == earliest && !out.hit && out.converged))) {
      out = toi, out.triangle = a.items[c.node], earliest = toi.time;
      // (Backward, a triangle counts as apart beyond half the tolerance, less rounding: the
      // band's contract. A face landing flat leaves every triangle under it at the hit's
      // gap, which the advancement closed to half the tolerance and no further.)
      if (out.hit)
        hit_pose = detail::Rigid(moving.at(earliest)),
        at_hit = ToolPlanes(tool.polytope(), hit_pose, d, moving.omega, moving.across,
                            radius + std::max(0.5 * tolerance - 1e-12 * reach, 1e-12 * reach));
    }
  };
  while (top > 0 && !settled()) {
    const Entry e = stack[--top];
    while (waiting > 0 && heap[0].time <= e.time && heap[0].time <= earliest) advance_next();
    const Octree::Node& n = a.nodes[e.node];
    if (e.time > earliest) continue;
    if (n.first_child >= 0) {  // the children the tool can reach in time, the soonest on top
      const int from = top;
      for (int c = n.first_child; c < n.first_child + n.child_count; ++c) {
        const Octree::Node& child = a.nodes[c];
        const Vector3d grow = child.box_half + Vector3d::Constant(r);
        double s = std::max(box_entry(c0, d, child.box_center - grow, child.box_center + grow),
                            planes.reach_time(child.box_center, child.box_half));
        if (line.on) s = std::max(s, line.box_entry(child.box_center, child.box_half));
        if (s <= earliest) stack[top++] = {c, s};
      }
      std::sort(stack + from, stack + top, later);
      continue;
    }
    for (int x = n.first; x < n.first + n.count; ++x) {  // (heap entries name the item x)
      const Eigen::Vector4d& sphere = a.spheres[a.items[x]];
      double s = sphere_entry(c0, d, sphere.head<3>(), sphere[3] + r);
      const Vector3d* corners = &a.item_corners[size_t(3) * x];
      if (s > earliest || planes.out_of_reach(corners, earliest, last_plane)) continue;  // (the cheap tests first)
      if ((s = std::max(s, planes.reach_time(corners))) > earliest) continue;
      if (line.on && (s = std::max(s, line.triangle_entry(corners, sphere, earliest))) > earliest) continue;
      // Of the triangles in reach at the start, those deepest in the tool's sphere first
      // (a key in [-1, 0)): the likeliest to be met at once, which ends the walk.
      if (s == 0) s = -std::max(0.0, 1 - (c0 - sphere.head<3>()).norm() / (sphere[3] + r));
      if (waiting == kHeapTriangles) advance_next();
      heap[waiting++] = {x, s};
      std::push_heap(heap, heap + waiting, later);
    }
  }
  while (waiting > 0 && heap[0].time <= earliest && !settled()) advance_next();
  out.iterations = iterations, out.tolerance = tolerance;
  if (out.hit) out.point_b -= radius * out.normal;  // (the tool's surface)
  if (out.hit || !out.converged) {  // back to the world frame
    out.normal = pose_a.linear() * out.normal, out.point_a = pose_a * out.point_a, out.point_b = pose_a * out.point_b;
  }
  return Status::Ok;
}

}  // namespace minksum
