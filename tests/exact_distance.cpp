// The exact triangle-triangle distance, an oracle independent of the library's
// triangle_distance: every coordinate taken exactly as a GMP rational, the enumeration of the
// pairs that can hold the closest points (an edge through the other's interior, vertex-face,
// edge-edge), every sign and every squared distance exact, and one rounding at the end (the
// square root of the least squared distance).
#include "exact_distance.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>

namespace minksum::test {

namespace {

struct Q3 {
  mpq_class x, y, z;
};

Q3 exact(const Eigen::Vector3d& v) { return {mpq_class(v.x()), mpq_class(v.y()), mpq_class(v.z())}; }
Q3 operator-(const Q3& a, const Q3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Q3 operator+(const Q3& a, const Q3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Q3 operator*(const Q3& a, const mpq_class& s) { return {a.x * s, a.y * s, a.z * s}; }
mpq_class dot(const Q3& a, const Q3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Q3 cross(const Q3& a, const Q3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
bool zero(const Q3& a) { return sgn(a.x) == 0 && sgn(a.y) == 0 && sgn(a.z) == 0; }

mpq_class clamp01(const mpq_class& t) { return t < 0 ? mpq_class(0) : t > 1 ? mpq_class(1) : t; }

// Squared distance from p to the segment a-b.
mpq_class point_segment(const Q3& p, const Q3& a, const Q3& b) {
  const Q3 d = b - a;
  const mpq_class len = dot(d, d);
  const mpq_class t = sgn(len) == 0 ? mpq_class(0) : clamp01(dot(p - a, d) / len);
  const Q3 r = p - (a + d * t);
  return dot(r, r);
}

// Whether x (in the plane of v, normal n != 0) lies in the closed triangle v.
bool in_triangle(const Q3& x, const Q3 (&v)[3], const Q3& n) {
  for (int k = 0; k < 3; ++k)
    if (sgn(dot(cross(v[(k + 1) % 3] - v[k], x - v[k]), n)) < 0) return false;
  return true;
}

// Squared distance from p to the triangle v.
mpq_class point_triangle(const Q3& p, const Q3 (&v)[3]) {
  mpq_class best = point_segment(p, v[0], v[1]);
  best = std::min(best, point_segment(p, v[1], v[2]));
  best = std::min(best, point_segment(p, v[2], v[0]));
  const Q3 n = cross(v[1] - v[0], v[2] - v[0]);
  if (zero(n)) return best;
  const mpq_class h = dot(n, p - v[0]), n2 = dot(n, n);
  if (in_triangle(p - n * (h / n2), v, n)) best = std::min(best, mpq_class(h * h / n2));
  return best;
}

// Squared distance between the segments p0-p1 and q0-q1: the convex quadratic's minimum over
// the unit square, at its interior critical point or on the square's boundary.
mpq_class segment_segment(const Q3& p0, const Q3& p1, const Q3& q0, const Q3& q1) {
  mpq_class best = std::min(
      {point_segment(p0, q0, q1), point_segment(p1, q0, q1), point_segment(q0, p0, p1), point_segment(q1, p0, p1)});
  const Q3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const mpq_class a = dot(d1, d1), b = dot(d1, d2), c = dot(d1, r), e = dot(d2, d2), f = dot(d2, r);
  const mpq_class den = a * e - b * b;
  if (sgn(den) != 0) {
    const mpq_class s = (b * f - c * e) / den, t = (a * f - b * c) / den;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
      const Q3 g = (p0 + d1 * s) - (q0 + d2 * t);
      best = std::min(best, dot(g, g));
    }
  }
  return best;
}

// Whether the segment p-q meets the triangle t with its ends on opposite sides of t's plane
// (or one end on it): the crossing point lies in t.
bool crosses(const Q3& p, const Q3& q, const Q3 (&t)[3]) {
  const Q3 n = cross(t[1] - t[0], t[2] - t[0]);
  if (zero(n)) return false;
  const mpq_class dp = dot(n, p - t[0]), dq = dot(n, q - t[0]);
  if (sgn(dp) * sgn(dq) > 0 || (sgn(dp) == 0 && sgn(dq) == 0)) return false;  // (in-plane: the other pairs)
  return in_triangle(p + (q - p) * (dp / (dp - dq)), t, n);
}

}  // namespace

double exact_triangle_distance(const Eigen::Vector3d (&s_in)[3], const Eigen::Vector3d (&t_in)[3]) {
  const Q3 s[3] = {exact(s_in[0]), exact(s_in[1]), exact(s_in[2])},
           t[3] = {exact(t_in[0]), exact(t_in[1]), exact(t_in[2])};
  for (int k = 0; k < 3; ++k)
    if (crosses(s[k], s[(k + 1) % 3], t) || crosses(t[k], t[(k + 1) % 3], s)) return 0;
  mpq_class best = point_triangle(s[0], t);
  for (int k = 0; k < 3; ++k) {
    best = std::min(best, point_triangle(s[k], t));
    best = std::min(best, point_triangle(t[k], s));
    for (int j = 0; j < 3; ++j) best = std::min(best, segment_segment(s[k], s[(k + 1) % 3], t[j], t[(j + 1) % 3]));
  }
  return std::sqrt(best.get_d());
}

}  // namespace minksum::test
