// The exact triangle-triangle distance, an oracle independent of the library's
// triangle_distance (and the same steps in double, a fast first opinion): every coordinate taken exactly as a GMP rational, the enumeration of the
// pairs that can hold the closest points (an edge through the other's interior, vertex-face,
// edge-edge), every sign and every squared distance exact, and one rounding at the end (the
// square root of the least squared distance).
#include "exact_distance.hpp"

#include <gmpxx.h>

#include <algorithm>
#include <cmath>

namespace minksum::test {

namespace {

// A point or vector with coordinates of type T: GMP's rationals (every step exact) or double
// (the same steps rounded: the fast oracle).
template <class T>
struct Q3 {
  T x, y, z;
};

int sgn(double v) { return (v > 0) - (v < 0); }
double to_double(const mpq_class& v) { return v.get_d(); }
double to_double(double v) { return v; }

template <class T>
Q3<T> exact(const Eigen::Vector3d& v) { return {T(v.x()), T(v.y()), T(v.z())}; }
template <class T>
Q3<T> operator-(const Q3<T>& a, const Q3<T>& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
template <class T>
Q3<T> operator+(const Q3<T>& a, const Q3<T>& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
template <class T>
Q3<T> operator*(const Q3<T>& a, const T& s) { return {a.x * s, a.y * s, a.z * s}; }
template <class T>
T dot(const Q3<T>& a, const Q3<T>& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
template <class T>
Q3<T> cross(const Q3<T>& a, const Q3<T>& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
template <class T>
bool zero(const Q3<T>& a) { return sgn(a.x) == 0 && sgn(a.y) == 0 && sgn(a.z) == 0; }

template <class T>
T clamp01(const T& t) { return t < 0 ? T(0) : t > 1 ? T(1) : t; }

// Squared distance from p to the segment a-b.
template <class T>
T point_segment(const Q3<T>& p, const Q3<T>& a, const Q3<T>& b) {
  const Q3<T> d = b - a;
  const T len = dot(d, d);
  const T t = sgn(len) == 0 ? T(0) : clamp01(T(dot(p - a, d) / len));
  const Q3<T> r = p - (a + d * t);
  return dot(r, r);
}

// Whether x (in the plane of v, normal n != 0) lies in the closed triangle v.
template <class T>
bool in_triangle(const Q3<T>& x, const Q3<T> (&v)[3], const Q3<T>& n) {
  for (int k = 0; k < 3; ++k)
    if (sgn(dot(cross(v[(k + 1) % 3] - v[k], x - v[k]), n)) < 0) return false;
  return true;
}

// Squared distance from p to the triangle v.
template <class T>
T point_triangle(const Q3<T>& p, const Q3<T> (&v)[3]) {
  T best = point_segment(p, v[0], v[1]);
  best = std::min(best, point_segment(p, v[1], v[2]));
  best = std::min(best, point_segment(p, v[2], v[0]));
  const Q3<T> n = cross(v[1] - v[0], v[2] - v[0]);
  if (zero(n)) return best;
  const T h = dot(n, p - v[0]), n2 = dot(n, n);
  if (in_triangle(p - n * T(h / n2), v, n)) best = std::min(best, T(h * h / n2));
  return best;
}

// Squared distance between the segments p0-p1 and q0-q1: the convex quadratic's minimum over
// the unit square, at its interior critical point or on the square's boundary.
template <class T>
T segment_segment(const Q3<T>& p0, const Q3<T>& p1, const Q3<T>& q0, const Q3<T>& q1) {
  T best = std::min(
      {point_segment(p0, q0, q1), point_segment(p1, q0, q1), point_segment(q0, p0, p1), point_segment(q1, p0, p1)});
  const Q3<T> d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const T a = dot(d1, d1), b = dot(d1, d2), c = dot(d1, r), e = dot(d2, d2), f = dot(d2, r);
  const T den = a * e - b * b;
  if (sgn(den) != 0) {
    const T s = (b * f - c * e) / den, t = (a * f - b * c) / den;
    if (s >= 0 && s <= 1 && t >= 0 && t <= 1) {
      const Q3<T> g = (p0 + d1 * s) - (q0 + d2 * t);
      best = std::min(best, dot(g, g));
    }
  }
  return best;
}

// Whether the segment p-q meets the triangle t with its ends on opposite sides of t's plane
// (or one end on it): the crossing point lies in t.
template <class T>
bool crosses(const Q3<T>& p, const Q3<T>& q, const Q3<T> (&t)[3]) {
  const Q3<T> n = cross(t[1] - t[0], t[2] - t[0]);
  if (zero(n)) return false;
  const T dp = dot(n, p - t[0]), dq = dot(n, q - t[0]);
  if (sgn(dp) * sgn(dq) > 0 || (sgn(dp) == 0 && sgn(dq) == 0)) return false;  // (in-plane: the other pairs)
  return in_triangle(p + (q - p) * T(dp / (dp - dq)), t, n);
}

template <class T>
double triangle_distance(const Eigen::Vector3d (&s_in)[3], const Eigen::Vector3d (&t_in)[3]) {
  const Q3<T> s[3] = {exact<T>(s_in[0]), exact<T>(s_in[1]), exact<T>(s_in[2])},
              t[3] = {exact<T>(t_in[0]), exact<T>(t_in[1]), exact<T>(t_in[2])};
  for (int k = 0; k < 3; ++k)
    if (crosses(s[k], s[(k + 1) % 3], t) || crosses(t[k], t[(k + 1) % 3], s)) return 0;
  T best = point_triangle(s[0], t);
  for (int k = 0; k < 3; ++k) {
    best = std::min(best, point_triangle(s[k], t));
    best = std::min(best, point_triangle(t[k], s));
    for (int j = 0; j < 3; ++j) best = std::min(best, segment_segment(s[k], s[(k + 1) % 3], t[j], t[(j + 1) % 3]));
  }
  return std::sqrt(to_double(best));
}

}  // namespace

double exact_triangle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3]) {
  return triangle_distance<mpq_class>(s, t);
}

double rounded_triangle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3]) {
  return triangle_distance<double>(s, t);
}

}  // namespace minksum::test
