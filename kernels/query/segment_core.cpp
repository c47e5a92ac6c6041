// Point and segment cores against any core. A segment s and a polytope p are read in p's body
// frame: their nearest points lie on a face of p that s does not lie wholly behind (an end
// over the face, s through it, or s against one of its edges), and where they meet, the depth
// is the separating axis theorem's on M = s (-) p.
#include "query/segment_core.hpp"

#include <minksum/shape.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/scale.hpp"
#include "geometry/closest.hpp"
#include "shape/shape_data.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

double largest(const Vector3d& v) { return v.cwiseAbs().maxCoeff(); }

// Rounding's scale at coordinates of magnitude `reach`: cores closer than this touch (the
// polytope query's touching tolerance).
double touching(double reach) { return 64 * std::numeric_limits<double>::epsilon() * reach; }

}  // namespace

double closest_segments(const Segment& a, const Segment& b, Vector3d& pa, Vector3d& pb) {
  if (a.s0 == a.s1) {  // a point: products of two coordinates, in range up to 1e100
    pa = a.s0, pb = b.s0 + nearest_on_segment(b.s0 - a.s0, b.s1 - a.s0) * (b.s1 - b.s0);
    return (pb - pa).norm();
  }
  // segment_segment forms products of four lengths: within [1e-60, 1e60] they stay normal;
  // beyond, relative to a's first end and scaled by a power of two.
  const double reach = std::max({largest(a.s0), largest(a.s1), largest(b.s0), largest(b.s1)});
  if (reach >= 1e-60 && reach <= 1e60) {
    segment_segment(a.s0, a.s1, b.s0, b.s1, pa, pb);
  } else {
    const Vector3d o = a.s0;
    const double k = scale_to_one(std::max({largest(a.s1 - o), largest(b.s0 - o), largest(b.s1 - o)}));
    Vector3d x, y;
    segment_segment(Vector3d::Zero(), k * (a.s1 - o), k * (b.s0 - o), k * (b.s1 - o), x, y);
    pa = o + x / k, pb = o + y / k;
  }
  return (pb - pa).norm();
}

namespace {

// A unit direction across two meeting segments whose difference has no interior (flat, a
// segment or a point), towards B's middle from A's: normal to both where they are not
// parallel, else normal to the one that is not a point, else z. Their depth along it is 0.
Vector3d across(const Segment& a, const Segment& b) {
  const Vector3d da = a.s1 - a.s0, db = b.s1 - b.s0;
  const Vector3d c = da.cross(db);
  Vector3d n = Vector3d::UnitZ();
  if (c.squaredNorm() > 1e-24 * da.squaredNorm() * db.squaredNorm() && c.allFinite())
    n = c.normalized();
  else if (da.squaredNorm() > 0)
    n = da.unitOrthogonal();
  else if (db.squaredNorm() > 0)
    n = db.unitOrthogonal();
  return n.dot((b.s0 + b.s1) - (a.s0 + a.s1)) < 0 ? Vector3d(-n) : n;
}

}  // namespace

void segment_pair(const Segment& a, const Segment& b, Proximity& out) {
  out.distance = closest_segments(a, b, out.point_a, out.point_b);
  const double reach = std::max({largest(a.s0), largest(a.s1), largest(b.s0), largest(b.s1)});
  if (out.distance > touching(reach)) return;
  out.intersecting = true, out.distance = 0;
  out.penetration_direction = across(a, b);
}

namespace {

// Whether x, on face f's plane, lies in its polygon (within tol).
bool in_face(const ConvexPolytope& p, const Face& face, const Vector3d& x, double tol) {
  const int n = int(face.loop.size());
  for (int k = 0; k < n; ++k) {
    const Vector3d& q0 = p.vertices[face.loop[k]];
    const Vector3d e = p.vertices[face.loop[k + 1 == n ? 0 : k + 1]] - q0;
    // (The loop runs counter-clockwise about the normal: inside is to the left of each edge.)
    if (face.normal.cross(e).dot(x - q0) < -tol * e.norm()) return false;
  }
  return true;
}

// The nearest points of segment s and face f of p (a solid p: only s's points in front of
// the face count, as its nearest points to a solid lie there): s through the face, an end over
// it, or s against one of its edges; where both ends lie over the face (on one side), the
// nearer end, and the edges are not read. Their distance (infinite where none counts). `over`:
// whether s lies over the face in front of it: for a point, it is then p's nearest point (the
// ball about the point through its foot lies in front of the face's plane, p behind it).
double segment_face(const Segment& s, const ConvexPolytope& p, int f, double tol, Vector3d& x, Vector3d& y,
                    bool& over) {
  const Face& face = p.faces[size_t(f)];
  const double h0 = face.normal.dot(s.s0) - face.offset, h1 = face.normal.dot(s.s1) - face.offset;
  over = false;
  if ((h0 <= 0 && h1 >= 0) || (h0 >= 0 && h1 <= 0)) {
    const Vector3d c = h0 == h1 ? s.s0 : Vector3d(s.s0 + h0 / (h0 - h1) * (s.s1 - s.s0));
    if (in_face(p, face, c, tol)) return x = y = c, 0.0;
  }
  double best = std::numeric_limits<double>::infinity();
  int ends_over = 0;
  for (const auto& [end, h] : {std::pair{&s.s0, h0}, std::pair{&s.s1, h1}}) {
    if (!p.flat && h < 0) continue;
    const Vector3d q = *end - h * face.normal;
    if (!in_face(p, face, q, 0)) continue;
    ++ends_over;
    if (std::abs(h) < best) best = std::abs(h), x = *end, y = q;
  }
  // Both ends over the face on one side: so is all of s, and its distance to the plane, linear
  // along it, is least at an end.
  over = ends_over == 2 && ((h0 >= 0 && h1 >= 0) || (h0 <= 0 && h1 <= 0));
  if (over) return best;
  const int n = int(face.loop.size());
  for (int k = 0; k < n; ++k) {
    const Segment edge{p.vertices[face.loop[k]], p.vertices[face.loop[k + 1 == n ? 0 : k + 1]]};
    Vector3d a, b;
    if (const double d = closest_segments(s, edge, a, b); d < best) best = d, x = a, y = b;
  }
  return best;
}

// The point of s whose move by `shift` lands in face f of p (the deepest pair of a segment
// level with the face): s clipped to the face's side planes after the move, its middle; `lowest`
// where the clip is empty (rounding).
Vector3d on_face(const Segment& s, const ConvexPolytope& p, int f, const Vector3d& shift, const Vector3d& lowest) {
  const Face& face = p.faces[size_t(f)];
  double t0 = 0, t1 = 1;
  const Vector3d d = s.s1 - s.s0;
  const int n = int(face.loop.size());
  for (int k = 0; k < n && t0 <= t1; ++k) {
    const Vector3d& q0 = p.vertices[face.loop[k]];
    const Vector3d inward = face.normal.cross(p.vertices[face.loop[k + 1 == n ? 0 : k + 1]] - q0);
    const double at = inward.dot(s.s0 + shift - q0), rate = inward.dot(d);
    if (rate > 0)
      t0 = std::max(t0, -at / rate);
    else if (rate < 0)
      t1 = std::min(t1, -at / rate);
    else if (at < 0)
      t0 = 2;
  }
  return t0 <= t1 ? Vector3d(s.s0 + 0.5 * (t0 + t1) * d) : lowest;
}

// The depth of a point or segment core s inside the polytope p (both in p's frame), which it
// meets: the separating axis theorem on M = s (-) p, whose facets' normals are p's face normals
// (both sides of a flat p) and, for a segment, its crosses with p's edges (Gregorius, "The
// separating axis test between convex polyhedra", GDC 2013). On a solid p only the edges whose
// Gauss-map arc the segment's great circle crosses give facets of M. Sets the depth, its
// direction u (p moves along it) and the deepest pair: point_a on s, point_b = point_a - depth u.
void segment_depth(const Segment& s, const ConvexPolytope& p, double tau, Proximity& out) {
  const Vector3d d = s.s1 - s.s0;
  const auto low = [&](const Vector3d& n) { return std::min(n.dot(s.s0), n.dot(s.s1)); };
  double depth = std::numeric_limits<double>::infinity();
  Vector3d u = Vector3d::UnitZ();
  int face = 0, edge = -1;
  const auto consider = [&](double h, const Vector3d& dir, int f, int e) {
    if (h < depth) depth = h, u = dir, face = f, edge = e;
  };
  const int F = p.flat ? 1 : int(p.faces.size());
  for (int f = 0; f < F; ++f) {  // h_M(-n) = max n . p - min n . s
    const Vector3d& n = p.faces[size_t(f)].normal;
    consider(p.faces[size_t(f)].offset - low(n), -n, f, -1);
    if (p.flat) consider(-low(Vector3d(-n)) - p.faces[size_t(f)].offset, n, f, -1);  // (its other side)
  }
  for (int e = 0; e < int(p.edges.size()) && d.squaredNorm() > 0; ++e) {
    const Edge& edge_e = p.edges[size_t(e)];
    Vector3d c = d.cross(p.vertices[edge_e.v1] - p.vertices[edge_e.v0]);
    const double len = c.norm();
    if (!(len > 0) || !std::isfinite(len)) continue;
    c /= len;
    if (!p.flat) {
      const Vector3d &nl = p.faces[edge_e.left].normal, &nr = p.faces[edge_e.right].normal;
      const double sl = nl.dot(d), sr = nr.dot(d);
      if ((sl > 0 && sr > 0) || (sl < 0 && sr < 0)) continue;  // the arc misses the great circle
      if (c.dot(nl + nr) < 0) c = -c;                           // outward at the edge
    } else {
      consider(support(p, Vector3d(-c)) - low(Vector3d(-c)), c, -1, e);  // (both signs)
    }
    consider(support(p, c) - low(c), -c, -1, e);
  }
  depth = std::max(depth, 0.0);
  Vector3d a, unused;
  if (edge >= 0) {  // s level along u: its point nearest the edge
    closest_segments(s, {p.vertices[p.edges[size_t(edge)].v0], p.vertices[p.edges[size_t(edge)].v1]}, a, unused);
  } else if (std::abs(u.dot(d)) <= tau) {  // level with the face: a point over it
    a = on_face(s, p, face, Vector3d(-depth * u), s.s0);
  } else {
    a = u.dot(s.s0) > u.dot(s.s1) ? s.s0 : s.s1;
  }
  out.intersecting = true, out.distance = 0;
  out.penetration_depth = depth, out.penetration_direction = u;
  out.point_a = a, out.point_b = a - depth * u;
}

// Whether the nearest points x (on s) and y (on face f of p) at distance d are proven: p lies
// below the plane through y normal to x - y, and s above the one through x (within slack).
bool proven(const Segment& s, const ConvexShape& shape, const Vector3d& x, const Vector3d& y, double d, double slack) {
  if (!(d > 64 * slack)) return false;
  const Vector3d n = (x - y) / d;
  if (std::min(n.dot(s.s0), n.dot(s.s1)) < n.dot(x) - slack) return false;
  return support(shape.polytope(), n) <= n.dot(y) + slack;
}

// A point and a box in the box's frame (centre c, axes R, half extents h): the point clamped
// into the box; inside (or within tol of its surface), the face nearest it.
void point_box(const Vector3d& x, const Box& box, double tol, Proximity& out) {
  const Vector3d c = box.rotation.transpose() * (x - box.center);
  const Vector3d q = c.cwiseMax(-box.half_extents).cwiseMin(box.half_extents);
  const double d = (c - q).norm();
  out.point_a = x;
  if (d > tol) {
    out.distance = d, out.point_b = box.center + box.rotation * q;
    return;
  }
  int k;
  (box.half_extents - c.cwiseAbs()).minCoeff(&k);
  const double depth = std::max(0.0, box.half_extents[k] - std::abs(c[k]));
  const Vector3d u = (c[k] < 0 ? 1.0 : -1.0) * box.rotation.col(k);  // the box moves off the point
  out.intersecting = true, out.distance = 0;
  out.penetration_depth = depth, out.penetration_direction = u;
  out.point_b = x - depth * u;
}

// A segment and a box in the box's frame (centre c, axes R, half extents h), in closed form:
// the squared distance of the point a + t d to the box is convex along the segment and
// piecewise quadratic, each piece fixed by the face planes the point lies beyond (at most six
// cuts where it crosses one). Its least value is where its slope, sum over those axes of
// d_i (x_i -+ h_i), turns from negative: the pieces are visited in order to the one where it
// does, and the slope, linear there, solved. Sets the distance and nearest points; false where
// they meet (within tol), for the depth.
bool segment_box(const Segment& s, const Box& box, double tol, Proximity& out) {
  const Eigen::Matrix3d& R = box.rotation;
  const Vector3d a = R.transpose() * (s.s0 - box.center), d = R.transpose() * (s.s1 - s.s0), h = box.half_extents;
  const auto slope = [&](double t) {
    const Vector3d x = a + t * d;
    return d.dot(x - x.cwiseMax(-h).cwiseMin(h));
  };
  double t = 0;
  if (slope(0) < 0) {
    t = 1;
    if (slope(1) > 0) {
      double cut[8] = {0};
      int n = 1;
      for (int i = 0; i < 3; ++i)
        for (const double side : {-h[i], h[i]})
          if (const double c = (side - a[i]) / d[i]; c > 0 && c < 1) cut[n++] = c;  // (d_i = 0: inf or NaN)
      for (int i = 2; i < n; ++i)  // (at most six cuts: an insertion sort)
        for (int j = i; j > 1 && cut[j] < cut[j - 1]; --j) std::swap(cut[j], cut[j - 1]);
      cut[n++] = 1;
      int k = 1;
      while (k < n - 1 && slope(cut[k]) < 0) ++k;
      const Vector3d mid = a + 0.5 * (cut[k - 1] + cut[k]) * d;
      double num = 0, den = 0;
      for (int i = 0; i < 3; ++i)
        if (mid[i] > h[i] || mid[i] < -h[i]) num += d[i] * (a[i] - (mid[i] > 0 ? h[i] : -h[i])), den += d[i] * d[i];
      t = den > 0 ? std::clamp(-num / den, cut[k - 1], cut[k]) : cut[k - 1];
    }
  }
  const Vector3d x = a + t * d, q = x.cwiseMax(-h).cwiseMin(h);
  const double dist = (x - q).norm();
  if (!(dist > tol)) return false;
  out.distance = dist, out.point_a = s.s0 + t * (s.s1 - s.s0), out.point_b = box.center + R * q;
  return true;
}

// The face of p whose plane s's middle lies farthest in front of: a cold query's guess of the
// face that holds the nearest points (right unless they lie past its edges).
int facing_face(const Segment& s, const ConvexPolytope& p, int faces) {
  const Vector3d m = 0.5 * (s.s0 + s.s1);
  int best = 0;
  double height = -std::numeric_limits<double>::infinity();
  for (int f = 0; f < faces; ++f)
    if (const double h = p.faces[size_t(f)].normal.dot(m) - p.faces[size_t(f)].offset; h > height) height = h, best = f;
  return best;
}

// A point or segment core s against a polytope core, both in its frame (out the same): a point
// and a box in closed form; the cached face (cold: the facing face) where its nearest points
// are proven, else the nearest points over the faces that s does not lie wholly behind, else,
// meeting p or inside it, the depth. True if the cached face answered.
bool body_proximity(const Segment& s, const ConvexShape& shape, int& cached, Proximity& out) {
  const ShapeData& data = *ShapeAccess::data(shape);
  const ConvexPolytope& p = shape.polytope();
  const double tol = touching(std::max({data.size, largest(s.s0), largest(s.s1)}));
  if (data.kind == ShapeData::Kind::Box) {
    if (s.s0 == s.s1) return point_box(s.s0, data.box, tol, out), false;
    if (segment_box(s, data.box, tol, out)) return cached = -1, false;
    return cached = -1, segment_depth(s, p, 4 * tol, out), false;
  }
  const int F = p.flat ? 1 : int(p.faces.size());
  Vector3d x, y;
  bool over;
  const bool warm = cached >= 0 && cached < F;
  const int first = warm ? cached : facing_face(s, p, F);
  if (const double d = segment_face(s, p, first, tol, x, y, over); proven(s, shape, x, y, d, tol))
    return cached = first, out.distance = d, out.point_a = x, out.point_b = y, warm;
  double best = std::numeric_limits<double>::infinity();
  bool inside = !p.flat;
  cached = -1;
  for (int f = 0; f < F; ++f) {
    const Face& face = p.faces[size_t(f)];
    inside = inside && face.normal.dot(s.s0) <= face.offset;
    if (!p.flat && std::max(face.normal.dot(s.s0), face.normal.dot(s.s1)) - face.offset < -tol)
      continue;  // wholly behind: no nearest point, no crossing here
    if (const double d = segment_face(s, p, f, tol, x, y, over); d < best) {
      best = d, out.point_a = x, out.point_b = y, cached = f;
      if (over && !p.flat && s.s0 == s.s1 && d > tol) return out.distance = d, false;  // (nearest: see segment_face)
    }
  }
  if (best > tol && !inside) return out.distance = best, false;
  cached = -1;
  segment_depth(s, p, 4 * tol, out);
  return false;
}

}  // namespace

bool segment_polytope(const Segment& a, const ConvexShape& b, const Eigen::Isometry3d& pose_b, int& face,
                      Proximity& out) {
  const Eigen::Isometry3d to_body = pose_b.inverse();
  const bool warm = body_proximity({to_body * a.s0, to_body * a.s1}, b, face, out);
  out.point_a = pose_b * out.point_a, out.point_b = pose_b * out.point_b;
  out.penetration_direction = pose_b.linear() * out.penetration_direction;
  return warm;
}

}  // namespace minksum::detail
