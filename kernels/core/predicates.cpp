// Filtered exact predicates: a floating-point filter first, the expansions (expansion.hpp) when
// it cannot decide (see predicates.hpp).
#include "core/predicates.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "core/expansion.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

int orient_exact(const Vector3d& p, const Vector3d& q, const Vector3d& r) {
  // Every one of the six products has a zero factor (axis-aligned and prism normals): 0. (No
  // product of three nonzero components underflows in the range the callers keep.)
  const auto zero_term = [](double x, double y, double z) { return x == 0 || y == 0 || z == 0; };
  if (zero_term(p.x(), q.y(), r.z()) && zero_term(p.x(), q.z(), r.y()) && zero_term(p.y(), q.z(), r.x()) &&
      zero_term(p.y(), q.x(), r.z()) && zero_term(p.z(), q.x(), r.y()) && zero_term(p.z(), q.y(), r.x()))
    return 0;
  // A repeated or exactly opposite row (identical and mirrored shapes, A and -A): 0.
  if (p == q || p == r || q == r || p == -q || p == -r || q == -r) return 0;
  return expansion::det3_sign(p.data(), q.data(), r.data());
}

namespace {

// A growing expansion, compressed when it passes 60 components (it then holds at most one
// component per 53 bits of exponent range: fewer than 45), in two buffers used in turn.
struct Accumulator {
  double buf[2][72];
  double* e = buf[0];
  int n = 0;
  // Adds the expansion x of k <= 4 components.
  void add(const double* x, int k) {
    double* h = e == buf[0] ? buf[1] : buf[0];
    n = n ? expansion::sum(n, e, k, x, h) : (std::copy(x, x + k, h), k);
    e = h;
    if (n > 60) compress();
  }
  // Shewchuk's compress: the same value in as few components as possible.
  void compress() {
    if (n == 0) return;
    double g[128];
    int bottom = n - 1;
    double q = e[bottom];
    for (int k = n - 2; k >= 0; --k) {
      const double enow = e[k], qnew = q + enow, small = enow - (qnew - q);
      if (small != 0) {
        g[bottom--] = qnew;
        q = small;
      } else {
        q = qnew;
      }
    }
    g[bottom] = q;
    int top = 0;
    for (int k = bottom + 1; k < n; ++k) {
      const double hnow = g[k], qnew = hnow + q, small = q - (qnew - hnow);
      if (small != 0) e[top++] = small;
      q = qnew;
    }
    e[top++] = q;
    n = top;
  }
  // The value rounded (the largest component dominates a compressed expansion), and whether
  // that is exact (one component).
  double value(bool& exact) {
    compress();
    exact &= n <= 1;
    return n ? e[n - 1] : 0.0;
  }
};

}  // namespace

namespace {

// The binary exponent e of a finite nonzero x with 2^(e-1) <= |x| < 2^e (std::frexp's), and
// 2^e, from the bits (no library call; subnormals, which the callers do not scale, excluded).
int exponent_of(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return int((bits >> 52) & 0x7ff) - 1022;
}
double power_of_two(int e) {  // for -1022 < e < 1024
  const std::uint64_t bits = std::uint64_t(e + 1023) << 52;
  double x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

// The Newell normal in double when that is exact: every coordinate an integer times 2^s with
// at most 24 bits (so each product has at most 48 and a sum of up to 32 of them at most 53),
// after scaling by a power of two; false otherwise (the expansions decide).
bool small_integer_newell(const std::vector<Vector3d>& points, const std::vector<int>& loop, Vector3d& out) {
  if (loop.size() > 16) return false;
  double top = 0;
  for (int v : loop) top = std::max(top, points[v].cwiseAbs().maxCoeff());
  if (!(top > 0x1p-400 && top < 0x1p400)) return false;
  const double up = power_of_two(24 - exponent_of(top));  // the largest coordinate now below 2^24
  Vector3d n = Vector3d::Zero();
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d a = points[loop[k]] * up, b = points[loop[(k + 1) % loop.size()]] * up;
    for (int d = 0; d < 3; ++d)
      if (double(std::int64_t(a[d])) != a[d]) return false;  // (|a| < 2^24: the cast is exact)
    n += a.cross(b);
  }
  out = n / (up * up);  // (an exact power of two)
  return true;
}

}  // namespace

Vector3d exact_newell(const std::vector<Vector3d>& points, const std::vector<int>& loop, bool* exact) {
  Vector3d v;
  if (small_integer_newell(points, loop, v)) {
    if (exact) *exact = true;
    return v;
  }
  // The loop scaled by a power of two to a largest coordinate near 1 (exact, and the products
  // neither underflow nor overflow): the normal's direction is the same.
  double top = 0;
  for (int i : loop) top = std::max(top, points[i].cwiseAbs().maxCoeff());
  const int e = top >= 0x1p-1000 ? exponent_of(top) : -1000;
  const double scale = power_of_two(-e / 2) * power_of_two(-e - (-e / 2));
  Accumulator n[3];
  bool ok = true;
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d a = points[loop[k]] * scale;
    const Vector3d b = points[loop[(k + 1) % loop.size()]] * scale;
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      double m[4];
      expansion::minor2(a[e], b[f], a[f], b[e], m);
      // A product that underflows is not exact (subnormal coordinates).
      const double scale = std::abs(a[e] * b[f]) + std::abs(a[f] * b[e]);
      if (scale != 0 && scale < 0x1p-900) ok = false;
      n[d].add(m, 4);
    }
  }
  v = Vector3d(n[0].value(ok), n[1].value(ok), n[2].value(ok));
  if (exact) *exact = ok;
  return v;
}

Vector3d newell_normal(const std::vector<Vector3d>& points, const std::vector<int>& loop, bool& exact) {
  Vector3d v;
  if ((exact = small_integer_newell(points, loop, v))) return v;
  // In double, kept when every component is surely nonzero (it clears its error bound: 2 m + 2
  // rounding errors of the sum of its 2 m products' magnitudes) or surely 0 (every product is
  // 0): its signs and its zeros are then the exact ones. Else the exact Newell normal, rounded.
  v.setZero();
  Vector3d magnitude = Vector3d::Zero();
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d& a = points[loop[k]];
    const Vector3d& b = points[loop[(k + 1) % loop.size()]];
    v += a.cross(b);
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      magnitude[d] += std::abs(a[e] * b[f]) + std::abs(a[f] * b[e]);
    }
  }
  const double relative = (2.0 * double(loop.size()) + 2) * 0x1p-52;
  for (int d = 0; d < 3; ++d)
    if (magnitude[d] != 0 && !(std::abs(v[d]) > relative * magnitude[d] && magnitude[d] > 0x1p-900))
      return exact_newell(points, loop, &exact);
  return v;
}

Vector3d exact_edge_cross(const Vector3d& p, const Vector3d& q, const Vector3d& n, bool* exact) {
  // q - p exactly (a rounded difference and its error, per coordinate), the points scaled by a
  // power of two to a largest coordinate near 1 (as in exact_newell).
  const double top = std::max(p.cwiseAbs().maxCoeff(), q.cwiseAbs().maxCoeff());
  const int e = top >= 0x1p-1000 ? exponent_of(top) : -1000;
  const double scale = power_of_two(-e / 2) * power_of_two(-e - (-e / 2));
  double d[3][2];
  for (int k = 0; k < 3; ++k) expansion::two_diff(q[k] * scale, p[k] * scale, d[k][0], d[k][1]);
  bool ok = true;
  Vector3d out;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    Accumulator acc;  // d_a n_b - d_b n_a over both parts of each difference
    for (int h = 0; h < 2; ++h) {
      double m[4];
      expansion::minor2(d[a][h], n[b], d[b][h], n[a], m);
      acc.add(m, 4);
    }
    out[k] = acc.value(ok);
  }
  if (exact) *exact = ok;
  return out;
}

Vector3d canonical_direction(const Vector3d& v, bool exact) {
  const double top = v.cwiseAbs().maxCoeff();
  if (!(top > 0)) return Vector3d::Zero();
  Vector3d w = v;
  // (Components far below the largest one, subnormal ones among them, are flushed below anyway.)
  const double least = std::min(
      {v.x() != 0 ? std::abs(v.x()) : top, v.y() != 0 ? std::abs(v.y()) : top, v.z() != 0 ? std::abs(v.z()) : top});
  if (exact && least > 0x1p-900 && top < 0x1p900) {
    // Integers m_k with v_k = m_k 2^low: low is the exponent of the lowest set bit of any
    // component (a double is its 53-bit significand times 2^(e - 53)); within 63 bits of range
    // the gcd is taken.
    int low = 1 << 20;
    for (int k = 0; k < 3; ++k)
      if (v[k] != 0) {
        const int e = exponent_of(v[k]);
        const std::uint64_t significand = std::uint64_t(std::abs(v[k]) * power_of_two(53 - e));
        low = std::min(low, e - 53 + __builtin_ctzll(significand));
      }
    if (exponent_of(top) - low <= 62 && low > -1000) {
      std::uint64_t g = 0, mk[3];
      const double down = power_of_two(-low);
      for (int k = 0; k < 3; ++k) g = std::gcd(g, mk[k] = std::uint64_t(std::abs(v[k]) * down));
      for (int k = 0; k < 3; ++k) w[k] = std::copysign(double(mk[k] / g), v[k]);  // fewer bits: exact
    }
  }
  // To a largest component in [0.5, 1): a power of two (in two steps where one would leave
  // the normal range).
  const int e = exponent_of(w.cwiseAbs().maxCoeff());
  const double half = power_of_two(-e / 2), rest = power_of_two(-e - (-e / 2));
  for (int k = 0; k < 3; ++k) {
    w[k] = w[k] * half * rest;
    if (std::abs(w[k]) < kTinyComponent) w[k] = 0;
  }
  return w;
}

}  // namespace minksum::detail
