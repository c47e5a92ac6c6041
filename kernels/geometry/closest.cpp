// Closest points of simple primitives: segments, triangles, and the corners of a box. The
// geometry stage: no shape, no sum, no kernel table below it.
#include <minksum/kernels.hpp>

#include "core/scale.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Vector3d;

namespace {

// Closest points of segments p0-p1 and q0-q1 (Ericson, "Real-Time Collision Detection", 2005,
// section 5.1.9), degenerate segments included; returns the squared distance.
double segment_segment(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0, const Vector3d& q1, Vector3d& cp,
                       Vector3d& cq) {
  const Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  double s = 0, t = 0;
  if (a == 0 && e == 0) {
    s = t = 0;
  } else if (a == 0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = d1.dot(r);
    if (e == 0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = d1.dot(d2);
      // a e - b^2 = |d1 x d2|^2 and b f - c e = (d1 x d2) . (d2 x r) (Lagrange's identity),
      // without the cancellation for near-parallel segments: as products of dots both lose
      // eps L^4, which is all of them for segments 1e9 times longer than apart (on needles
      // 1.4e86 long: 2.03e76 for 1.30e76).
      const Vector3d x = d1.cross(d2);
      const double denom = x.squaredNorm();
      s = denom > 0 ? std::clamp(x.dot(d2.cross(r)) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0)
        t = 0, s = std::clamp(-c / a, 0.0, 1.0);
      else if (t > 1)
        t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  cp = p0 + s * d1, cq = q0 + t * d2;
  return (cp - cq).squaredNorm();
}

// The projection of p onto the plane of triangle v (normal n, not flat; inv = 1 / |n|^2), if it
// lies inside:
// edge tests against the normal. Elsewhere an edge of v holds p's closest point, which the
// edge pairs of triangle_distance cover. (Ericson's barycentric region tests, section 5.1.5,
// cancel on slivers: they put a vertex lying in a 0.06-wide, 700-long triangle 9e-7 away.)
bool onto_face(const Vector3d& p, const Vector3d (&v)[3], const Vector3d& n, double inv, Vector3d& q) {
  q = p - n * (n.dot(p - v[0]) * inv);
  return (v[1] - v[0]).cross(q - v[0]).dot(n) >= 0 && (v[2] - v[1]).cross(q - v[1]).dot(n) >= 0 &&
         (v[0] - v[2]).cross(q - v[2]).dot(n) >= 0;
}

// Where the segment p-q crosses the interior of triangle t (normal n, not degenerate), if it
// does with its endpoints strictly on opposite sides of the plane.
bool pierces(const Vector3d& p, const Vector3d& q, const Vector3d (&t)[3], const Vector3d& n, Vector3d& x) {
  const double dp = n.dot(p - t[0]), dq = n.dot(q - t[0]);
  if (!((dp > 0 && dq < 0) || (dp < 0 && dq > 0))) return false;
  x = p + dp / (dp - dq) * (q - p);
  for (int k = 0; k < 3; ++k)
    if ((t[(k + 1) % 3] - t[k]).cross(x - t[k]).dot(n) < 0) return false;
  return true;
}

// The triangle turned (cyclically: the same orientation) so that its first corner is opposite
// its longest edge: the normal (v1 - v0) x (v2 - v0) is then the cross product of the two
// shortest edges, whose rounding relative to the area, eps |e1| |e2| / 2A, is the least. (Of
// a needle 1e10 long and 100 wide, the normal from its far corner turns by 3e-8, which moves
// its plane by 400 at the near end: distance 0 for shapes 24.7 apart.)
void apex_first(Vector3d (&v)[3]) {
  const double e[3] = {(v[1] - v[0]).squaredNorm(), (v[2] - v[1]).squaredNorm(), (v[0] - v[2]).squaredNorm()};
  const int k = e[1] >= e[0] && e[1] >= e[2] ? 0 : e[2] >= e[0] ? 1 : 2;  // e[1] is opposite v0
  std::rotate(v, v + k, v + 3);
}

}  // namespace

double triangle_distance(const Vector3d (&s_in)[3], const Vector3d (&t_in)[3], Vector3d& ps, Vector3d& pt) {
  // Work relative to one corner (coordinates far from the origin keep their precision), scaled
  // by a power of two to about 1 (exact): the segment test multiplies four coordinates, which
  // would overflow beyond 1e77 (an infinite distance at 1e86) or underflow.
  const Vector3d o = s_in[0];
  double size = 0;
  for (const Vector3d* v : {&s_in[1], &s_in[2], &t_in[0], &t_in[1], &t_in[2]})
    size = std::max(size, (*v - o).cwiseAbs().maxCoeff());
  const double shrink = detail::scale_to_one(size);
  Vector3d s[3] = {Vector3d::Zero(), shrink * (s_in[1] - o), shrink * (s_in[2] - o)};
  Vector3d t[3] = {shrink * (t_in[0] - o), shrink * (t_in[1] - o), shrink * (t_in[2] - o)};
  apex_first(s), apex_first(t);
  const Vector3d ns = (s[1] - s[0]).cross(s[2] - s[0]), nt = (t[1] - t[0]).cross(t[2] - t[0]);
  // Degenerate (zero-area) triangles have no face region; their edges cover them.
  const auto flat = [](const Vector3d& n, const Vector3d(&v)[3]) {
    const double scale =
        std::max({(v[1] - v[0]).squaredNorm(), (v[2] - v[0]).squaredNorm(), (v[2] - v[1]).squaredNorm()});
    return !(n.squaredNorm() > 1e-24 * scale * scale);
  };
  const bool s_flat = flat(ns, s), t_flat = flat(nt, t);
  // Intersecting, not coplanar: an edge of one crosses the other's interior. Impossible if
  // either triangle lies strictly on one side of the other's plane (the common case).
  const auto one_side = [](const Vector3d& n, const Vector3d& p, const Vector3d(&q)[3]) {
    const double d0 = n.dot(q[0] - p), d1 = n.dot(q[1] - p), d2 = n.dot(q[2] - p);
    return (d0 > 0 && d1 > 0 && d2 > 0) || (d0 < 0 && d1 < 0 && d2 < 0);
  };
  // (A flat triangle's normal is rounding noise: it separates nothing.)
  const bool apart = (!s_flat && one_side(ns, s[0], t)) || (!t_flat && one_side(nt, t[0], s));
  Vector3d x;
  for (int k = 0; k < 3 && !apart; ++k) {
    if (!t_flat && pierces(s[k], s[(k + 1) % 3], t, nt, x)) {
      ps = pt = x / shrink + o;
      return 0;
    }
    if (!s_flat && pierces(t[k], t[(k + 1) % 3], s, ns, x)) {
      ps = pt = x / shrink + o;
      return 0;
    }
  }
  // Otherwise the closest pair is edge-edge or vertex-face (coplanar overlap shows as 0 there).
  double best = std::numeric_limits<double>::infinity();
  Vector3d bs = s[0], bt = t[0], cp, cq;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const double d2 = segment_segment(s[i], s[(i + 1) % 3], t[j], t[(j + 1) % 3], cp, cq);
      if (d2 < best) best = d2, bs = cp, bt = cq;
    }
  const double inv_s = s_flat ? 0.0 : 1 / ns.squaredNorm(), inv_t = t_flat ? 0.0 : 1 / nt.squaredNorm();
  for (int k = 0; k < 3; ++k) {
    if (!t_flat && onto_face(s[k], t, nt, inv_t, cq))
      if (const double d2 = (s[k] - cq).squaredNorm(); d2 < best) best = d2, bs = s[k], bt = cq;
    if (!s_flat && onto_face(t[k], s, ns, inv_s, cp))
      if (const double d2 = (t[k] - cp).squaredNorm(); d2 < best) best = d2, bs = cp, bt = t[k];
  }
  ps = bs / shrink + o, pt = bt / shrink + o;
  return std::sqrt(best) / shrink;
}

Vector3d box_corner(const Box& box, int code) {
  Vector3d p = box.center;
  for (int a = 0; a < 3; ++a) p += ((code >> a & 1) ? 1.0 : -1.0) * box.half_extents[a] * box.rotation.col(a);
  return p;
}

}  // namespace minksum
