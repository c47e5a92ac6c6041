// Closest points of simple primitives: segments, triangles, and the corners of a box. The
// geometry stage: no shape, no sum, no kernel table below it.
#include <minksum/kernels.hpp>

#include "core/expansion.hpp"
#include "core/hull.hpp"
#include "core/predicates.hpp"
#include "core/scale.hpp"
#include "geometry/closest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

namespace minksum {

using Eigen::Vector3d;

double detail::segment_segment(const Vector3d& p0, const Vector3d& p1, const Vector3d& q0, const Vector3d& q1, Vector3d& cp,
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

namespace {

// The plane of a triangle v: its normal n = (v1 - v0) x (v2 - v0); for a sliver (sine under
// 1e-4, as the batched kernel routes here) that normal computed accurately (accurate_normal),
// |n|_1 and the largest coordinate of an edge, which bound the rounding of its face test.
struct Plane {
  Vector3d n;
  bool flat = false, sliver = false;  // (flat: zero area, or within rounding of it)
  double n1 = 0, reach = 0;
};

// The exact normal (v1 - v0) x (v2 - v0) of the doubles v, each component an expansion of at
// most 16 terms (the edges as two_diff leaves them, their products exact). A rounded normal
// (accurate_normal: a few ulps) tilts the plane through a sliver's edge along it by ulps of the
// sliver's length: more than a point beyond its sharp corner lies off that edge (a corner
// 2.9e76 beyond a needle's apex, 1.4e86 long, read as inside it: 2.5e72 apart).
struct ExactNormal {
  double terms[3][16];
  detail::ExactVector n;
  explicit ExactNormal(const Vector3d (&v)[3]) {
    using namespace detail::expansion;
    double e[2][3][2];  // edge r (v_{r+1} - v0), component d: (lo, hi), zeros dropped
    int len[2][3];
    for (int r = 0; r < 2; ++r)
      for (int d = 0; d < 3; ++d) {
        double hi, lo;
        two_diff(v[r + 1][d], v[0][d], hi, lo);
        len[r][d] = 0;
        if (lo != 0) e[r][d][len[r][d]++] = lo;
        if (hi != 0) e[r][d][len[r][d]++] = hi;
      }
    // x * y exactly (x, y expansions of up to 2 terms): up to 8 terms.
    const auto product = [](const double* x, int nx, const double* y, int ny, double* out) -> int {
      if (nx == 0 || ny == 0) return 0;
      double a[4], b[4];
      const int na = scale(nx, x, y[0], a);
      if (ny == 1) return int(std::copy(a, a + na, out) - out);
      const int nb = scale(nx, x, y[1], b);
      return sum(na, a, nb, b, out);
    };
    for (int d = 0; d < 3; ++d) {
      const int i = (d + 1) % 3, j = (d + 2) % 3;
      double plus[8], minus[8];
      const int np = product(e[0][i], len[0][i], e[1][j], len[1][j], plus);
      const int nm = product(e[0][j], len[0][j], e[1][i], len[1][i], minus);
      for (int k = 0; k < nm; ++k) minus[k] = -minus[k];
      int m = 0;
      if (np > 0 && nm > 0)
        m = sum(np, plus, nm, minus, terms[d]);
      else if (np > 0)
        m = int(std::copy(plus, plus + np, terms[d]) - terms[d]);
      else if (nm > 0)
        m = int(std::copy(minus, minus + nm, terms[d]) - terms[d]);
      n.terms[d] = terms[d], n.count[d] = m == 1 && terms[d][0] == 0 ? 0 : m;
    }
    n.sign = 1;
  }
  ExactNormal(const ExactNormal&) = delete;  // (n points into terms)
  ExactNormal& operator=(const ExactNormal&) = delete;
};

// The exact sign of det[b - a; p - a; n]: the side of the plane through the edge a-b along n on
// which p lies (the differences as two_diff leaves them, and expansions).
int beside_exact(const Vector3d& a, const Vector3d& b, const Vector3d& p, const detail::ExactVector& n) {
  double terms[2][3][2];
  detail::ExactVector x[3];
  const Vector3d* to[2] = {&b, &p};
  for (int r = 0; r < 2; ++r) {
    for (int k = 0; k < 3; ++k) {
      double hi, lo;
      detail::expansion::two_diff((*to[r])[k], a[k], hi, lo);
      int m = 0;  // (increasing magnitude, zeros dropped)
      if (lo != 0) terms[r][k][m++] = lo;
      if (hi != 0) terms[r][k][m++] = hi;
      x[r].terms[k] = terms[r][k], x[r].count[k] = m;
    }
    x[r].sign = 1;
  }
  x[2] = n;
  return detail::orient_exact(x[0], x[1], x[2]);
}

// The projection q of p onto the plane of triangle v (not flat; inv = 1 / |n|^2), if it lies
// inside: edge tests against the normal. Elsewhere an edge of v holds p's closest point, which
// the edge pairs of triangle_distance cover. (Ericson's barycentric region tests, section 5.1.5,
// cancel on slivers: they put a vertex lying in a 0.06-wide, 700-long triangle 9e-7 away.) A
// sliver's edge tests are ill-conditioned too (a point 2e-10 beyond its sharp corner, on its
// plane, read as inside: distance 0), so there they are exact where their rounding bound (a
// few eps |n|_1 |e| |p - v_k|; 1e-14 of it, taken once) cannot tell; they read p, not q (q - p
// is along n).
bool onto_face(const Vector3d& p, const Vector3d (&v)[3], const Plane& plane, double inv, Vector3d& q) {
  const Vector3d& n = plane.n;
  q = p - n * (n.dot(p - v[0]) * inv);
  if (!plane.sliver)
    return (v[1] - v[0]).cross(q - v[0]).dot(n) >= 0 && (v[2] - v[1]).cross(q - v[1]).dot(n) >= 0 &&
           (v[0] - v[2]).cross(q - v[2]).dot(n) >= 0;
  const double slack = 1e-14 * plane.n1 * plane.reach * ((p - v[0]).cwiseAbs().maxCoeff() + plane.reach);
  std::optional<ExactNormal> exact;
  for (int k = 0; k < 3; ++k) {
    const Vector3d &a = v[k], &b = v[(k + 1) % 3];
    const double d = (b - a).cross(p - a).dot(n);
    if (d < -slack) return false;
    if (d <= slack) {  // (the exact normal, once: rare)
      if (!exact) exact.emplace(v);
      if (beside_exact(a, b, p, exact->n) < 0) return false;
    }
  }
  return true;
}

// Where the segment p-q crosses triangle t (not degenerate), if it does with its endpoints
// strictly on opposite sides of the plane. Decided exactly: the segment's line passes every
// edge of t on one side (orient3d). A crossing point computed in doubles carries eps |q - p|
// of rounding, which can dwarf a small triangle: a sliver's edge at 1e86 "crossed" one 252
// across. The point is then computed, as the witness.
bool pierces(const Vector3d& p, const Vector3d& q, const Vector3d (&t)[3], const Plane& plane, Vector3d& x) {
  // The sides of t's plane, exactly for the doubles given (a plane 1e86 long read in doubles put
  // a triangle 252 across on both of its sides): n . (p - t0) where it clears its rounding (the
  // normal's, at most 4 eps |e1| |e2| a component, the difference's and the sum's), else orient3d.
  const double dp = plane.n.dot(p - t[0]), dq = plane.n.dot(q - t[0]);
  const double err = 2e-14 * (t[1] - t[0]).cwiseAbs().maxCoeff() * (t[2] - t[0]).cwiseAbs().maxCoeff();
  const auto side = [&](double d, const Vector3d& a) {
    return std::abs(d) > err * (a - t[0]).cwiseAbs().maxCoeff() ? (d > 0 ? 1 : -1) : detail::orient3d(t[0], t[1], t[2], a);
  };
  const int sp = side(dp, p), sq = side(dq, q);
  if (sp == 0 || sq == 0 || sp == sq) return false;
  int pos = 0, neg = 0;
  for (int k = 0; k < 3; ++k) {
    const int o = detail::orient3d(p, q, t[k], t[(k + 1) % 3]);
    pos += o > 0, neg += o < 0;
  }
  if (pos > 0 && neg > 0) return false;
  x = p + (dp != dq ? std::clamp(dp / (dp - dq), 0.0, 1.0) : 0.5) * (q - p);
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

// The normal (v1 - v0) x (v2 - v0) of triangle v to a few ulps of its length, however thin the
// triangle. In doubles the cross product of two nearly parallel edges errs by eps |e1| |e2|
// against a length of |e1| |e2| sin t, and rounding an edge turns it by eps as well: a sliver's
// normal turned by eps / sin t, which tilts its plane by that much of its length. (A triangle
// corner 2.5e76 from a sliver of 2e-10 rad reaching 1.4e86 read 1.1e76 from it: a fuzz_query
// finding.) Here each edge is exact as a two-term sum (two_diff) and the leading minors are
// exact (minor2). It is the normal of v as given: the shifted corners every test reads.
Vector3d accurate_normal(const Vector3d (&v)[3]) {
  using namespace detail::expansion;
  double h1[3], l1[3], h2[3], l2[3];
  for (int d = 0; d < 3; ++d) two_diff(v[1][d], v[0][d], h1[d], l1[d]), two_diff(v[2][d], v[0][d], h2[d], l2[d]);
  Vector3d n;
  for (int d = 0; d < 3; ++d) {
    const int i = (d + 1) % 3, j = (d + 2) % 3;
    double e[4];
    minor2(h1[i], h2[j], h1[j], h2[i], e);  // h1_i h2_j - h1_j h2_i exactly (smallest term first)
    n[d] = ((e[0] + e[1]) + e[2]) + e[3] + ((h1[i] * l2[j] + l1[i] * h2[j]) - (h1[j] * l2[i] + l1[j] * h2[i]));
  }
  return n;
}

// v's plane: a sliver's normal (its smallest angle's sine under 1e-4, as the batched kernel
// routes here) accurate, any other's within rounding already (and a repeated corner's, 0, stays
// 0: flat). The smallest angle, not the one at v0: a needle's is at its apex, where its two long
// edges meet, and only the exact edge tests tell a point just beyond that apex from one inside
// (a corner 2.9e76 beyond the apex of a needle 1.4e86 long read 2.5e72 from it).
// Flat: |n|^2 within 1e-24 of the longest edge's to the fourth (v2 - v1, apex_first's).
Plane plane_of(const Vector3d (&v)[3]) {
  const Vector3d e1 = v[1] - v[0], e2 = v[2] - v[0], n = e1.cross(e2);
  const double n2 = n.squaredNorm(), l1 = e1.squaredNorm(), l2 = e2.squaredNorm();
  const double longest = std::max({l1, l2, (v[2] - v[1]).squaredNorm()});
  Plane plane{n};
  plane.flat = !(n2 > 1e-24 * longest * longest);
  if (plane.flat || !(n2 < 1e-8 * longest * std::max(l1, l2))) return plane;
  plane.n = accurate_normal(v), plane.sliver = true, plane.n1 = plane.n.cwiseAbs().sum();
  plane.reach = std::max({e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff(), (v[2] - v[1]).cwiseAbs().maxCoeff()});
  return plane;
}

// Which edges and corners of triangle v to test: all, unless corners repeat (a segment as
// (p, q, q), a point as (p, p, p): the mesh queries' point and segment cores), where an edge of
// length 0 or one already listed, and a corner already listed, would only repeat a test.
void distinct_parts(const Vector3d (&v)[3], bool (&edge)[3], bool (&corner)[3]) {
  for (int k = 0; k < 3; ++k) {
    const Vector3d &a = v[k], &b = v[(k + 1) % 3];
    edge[k] = a != b, corner[k] = true;
    for (int j = 0; j < k; ++j) {
      const Vector3d &c = v[j], &d = v[(j + 1) % 3];
      edge[k] = edge[k] && !(edge[j] && ((a == c && b == d) || (a == d && b == c)));
      corner[k] = corner[k] && v[j] != a;
    }
  }
  if (!edge[0] && !edge[1] && !edge[2]) edge[0] = true;  // (a point: its one edge, of length 0)
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
  const Plane s_plane = plane_of(s), t_plane = plane_of(t);
  const Vector3d &ns = s_plane.n, &nt = t_plane.n;
  // Degenerate (zero-area) triangles have no face region; their edges cover them.
  const bool s_flat = s_plane.flat, t_flat = t_plane.flat;
  bool s_edge[3] = {true, true, true}, t_edge[3] = {true, true, true};
  bool s_corner[3] = {true, true, true}, t_corner[3] = {true, true, true};
  if (s_flat) distinct_parts(s, s_edge, s_corner);
  if (t_flat) distinct_parts(t, t_edge, t_corner);
  // Intersecting, not coplanar: an edge of one crosses the other's interior. Impossible if
  // either triangle lies strictly on one side of the other's plane (the common case).
  // (In doubles: a shortcut only. Where rounding calls a pair apart that touches, the distance
  // below is within rounding of 0; the other way, the piercing tests are exact.)
  const auto one_side = [](const Vector3d& n, const Vector3d& p, const Vector3d(&q)[3]) {
    const double d0 = n.dot(q[0] - p), d1 = n.dot(q[1] - p), d2 = n.dot(q[2] - p);
    return (d0 > 0 && d1 > 0 && d2 > 0) || (d0 < 0 && d1 < 0 && d2 < 0);
  };
  // (A flat triangle's normal is rounding noise: it separates nothing.)
  const bool apart = (!s_flat && one_side(ns, s[0], t)) || (!t_flat && one_side(nt, t[0], s));
  Vector3d x;
  for (int k = 0; k < 3 && !apart; ++k) {
    if (!t_flat && s_edge[k] && pierces(s[k], s[(k + 1) % 3], t, t_plane, x)) {
      ps = pt = x / shrink + o;
      return 0;
    }
    if (!s_flat && t_edge[k] && pierces(t[k], t[(k + 1) % 3], s, s_plane, x)) {
      ps = pt = x / shrink + o;
      return 0;
    }
  }
  // Otherwise the closest pair is edge-edge or vertex-face (coplanar overlap shows as 0 there).
  double best = std::numeric_limits<double>::infinity();
  Vector3d bs = s[0], bt = t[0], cp, cq;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      if (!s_edge[i] || !t_edge[j]) continue;
      const double d2 = detail::segment_segment(s[i], s[(i + 1) % 3], t[j], t[(j + 1) % 3], cp, cq);
      if (d2 < best) best = d2, bs = cp, bt = cq;
    }
  const double inv_s = s_flat ? 0.0 : 1 / ns.squaredNorm(), inv_t = t_flat ? 0.0 : 1 / nt.squaredNorm();
  for (int k = 0; k < 3; ++k) {
    if (!t_flat && s_corner[k] && onto_face(s[k], t, t_plane, inv_t, cq))
      if (const double d2 = (s[k] - cq).squaredNorm(); d2 < best) best = d2, bs = s[k], bt = cq;
    if (!s_flat && t_corner[k] && onto_face(t[k], s, s_plane, inv_s, cp))
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

// By Voronoi regions (Ericson, "Real-Time Collision Detection", 2005, sections 5.1.2, 5.1.5
// and 5.1.6).
bool detail::nearest_on_simplex(const Vector3d* w, int n, double (&lambda)[4]) {
  for (double& l : lambda) l = 0;
  if (n == 1) return lambda[0] = 1, true;
  if (n == 2) {
    const double t = nearest_on_segment(w[0], w[1]);
    return lambda[0] = 1 - t, lambda[1] = t, true;
  }
  // Triangle (i, j, k) of w: Ericson's ClosestPtPointTriangle with the query point at the origin.
  const auto triangle = [&](int i, int j, int k, double(&l)[4]) {
    for (double& x : l) x = 0;
    const Vector3d &a = w[i], ab = w[j] - a, ac = w[k] - a;
    const double d1 = -ab.dot(a), d2 = -ac.dot(a);
    if (d1 <= 0 && d2 <= 0) return void(l[i] = 1);
    const double d3 = -ab.dot(w[j]), d4 = -ac.dot(w[j]);
    if (d3 >= 0 && d4 <= d3) return void(l[j] = 1);
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
      const double v = d1 / (d1 - d3);
      return void((l[i] = 1 - v, l[j] = v));
    }
    const double d5 = -ab.dot(w[k]), d6 = -ac.dot(w[k]);
    if (d6 >= 0 && d5 <= d6) return void(l[k] = 1);
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
      const double t = d2 / (d2 - d6);
      return void((l[i] = 1 - t, l[k] = t));
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {
      const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
      return void((l[j] = 1 - t, l[k] = t));
    }
    const double denom = va + vb + vc;
    const double v = vb / denom, t = vc / denom;
    l[i] = 1 - v - t, l[j] = v, l[k] = t;
  };
  const auto dist2 = [&](const double(&l)[4]) {
    Vector3d p = Vector3d::Zero();
    for (int k = 0; k < n; ++k) p += l[k] * w[k];
    return p.squaredNorm();
  };
  if (n == 3) return triangle(0, 1, 2, lambda), true;
  // Tetrahedron: the nearest of the faces whose plane has the origin on the far side from the
  // fourth point (none: the origin is inside). A tetrahedron flat to rounding has no inside
  // whose sign can be trusted (face-to-face pairs 1e-6 apart would read as "inside"): every
  // face is a candidate.
  static constexpr int kFace[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  const Vector3d e1 = w[1] - w[0], e2 = w[2] - w[0], e3 = w[3] - w[0];
  const bool flat = !(std::abs(e1.dot(e2.cross(e3))) > 1e-12 * e1.norm() * e2.norm() * e3.norm());
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : kFace) {
    const Vector3d nf = (w[f[1]] - w[f[0]]).cross(w[f[2]] - w[f[0]]);
    if (!flat && -w[f[0]].dot(nf) * (w[f[3]] - w[f[0]]).dot(nf) > 0) continue;
    double l[4];
    triangle(f[0], f[1], f[2], l);
    if (const double d = dist2(l); d < best) best = d, std::copy(l, l + 4, lambda);
  }
  return best < std::numeric_limits<double>::infinity();
}

namespace detail {

double ball_exit(const Eigen::Vector3d& c, const Eigen::Vector3d& u, double r) {
  const double along = u.dot(c), across2 = (c - along * u).squaredNorm();
  return across2 <= r * r ? along + std::sqrt(r * r - across2) : -std::numeric_limits<double>::infinity();
}

double cylinder_exit(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& u, double r) {
  // |lambda w - c| = r across the axis (w, c: u and a with their parts along d removed).
  const Eigen::Vector3d d = b - a;
  const double len2 = d.squaredNorm(), none = -std::numeric_limits<double>::infinity();
  if (!(len2 > 0)) return none;
  const Eigen::Vector3d w = u - u.dot(d) / len2 * d, c = a - a.dot(d) / len2 * d;
  const double ww = w.squaredNorm(), wc = w.dot(c), disc = wc * wc - ww * (c.squaredNorm() - r * r);
  if (!(ww > 0) || disc < 0) return none;
  const double lambda = (wc + std::sqrt(disc)) / ww, s = (lambda * u - a).dot(d) / len2;
  return s >= 0 && s <= 1 ? lambda : none;
}

}  // namespace detail

}  // namespace minksum
