#include "predicates.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

#include "expansion.hpp"

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

// A growing expansion of at most 64 components, compressed when it fills (it then holds at
// most one component per 53 bits of exponent range: fewer than 45).
struct Accumulator {
  double e[128];
  int n = 0;
  void add(double x) {
    if (x == 0) return;
    double h[129];
    const int m = n ? expansion::sum(n, e, 1, &x, h) : (h[0] = x, 1);
    std::copy(h, h + m, e), n = m;
    if (n >= 64) compress();
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

Vector3d exact_newell(const std::vector<Vector3d>& points, const std::vector<int>& loop, bool* exact) {
  Accumulator n[3];
  bool ok = true;
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d& a = points[loop[k]];
    const Vector3d& b = points[loop[(k + 1) % loop.size()]];
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      double m[4];
      expansion::minor2(a[e], b[f], a[f], b[e], m);
      // A product that underflows is not exact (subnormal coordinates).
      const double scale = std::abs(a[e] * b[f]) + std::abs(a[f] * b[e]);
      if (scale != 0 && scale < 0x1p-900) ok = false;
      for (double x : m) n[d].add(x);
    }
  }
  const Vector3d v(n[0].value(ok), n[1].value(ok), n[2].value(ok));
  if (exact) *exact = ok;
  return v;
}

Vector3d exact_edge_cross(const Vector3d& p, const Vector3d& q, const Vector3d& n, bool* exact) {
  double d[3][2];  // q - p exactly: a rounded difference and its error, per coordinate
  for (int k = 0; k < 3; ++k) expansion::two_diff(q[k], p[k], d[k][0], d[k][1]);
  bool ok = true;
  Vector3d out;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    Accumulator acc;  // d_a n_b - d_b n_a over both parts of each difference
    for (int h = 0; h < 2; ++h) {
      double m[4];
      expansion::minor2(d[a][h], n[b], d[b][h], n[a], m);
      for (double x : m) acc.add(x);
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
  if (exact) {
    // Integers m_k with v_k = m_k 2^low: low is the exponent of the lowest set bit of any
    // component; within 63 bits of range the gcd is taken.
    int low = 1 << 20;
    for (int k = 0; k < 3; ++k)
      if (v[k] != 0) {
        int e;
        const double m = std::frexp(v[k], &e);  // v = m 2^e, 0.5 <= |m| < 1: 53 bits of m
        const std::int64_t bits = std::int64_t(std::ldexp(std::abs(m), 53));
        low = std::min(low, e - 53 + __builtin_ctzll(std::uint64_t(bits)));
      }
    int high;
    std::frexp(top, &high);
    if (high - low <= 62) {
      std::uint64_t g = 0, mk[3];
      for (int k = 0; k < 3; ++k) g = std::gcd(g, mk[k] = std::uint64_t(std::ldexp(std::abs(v[k]), -low)));
      for (int k = 0; k < 3; ++k) w[k] = std::copysign(double(mk[k] / g), v[k]);  // fewer bits: exact
    }
  }
  int e;
  std::frexp(w.cwiseAbs().maxCoeff(), &e);
  for (int k = 0; k < 3; ++k) {
    w[k] = std::ldexp(w[k], -e);
    if (std::abs(w[k]) < kTinyComponent) w[k] = 0;
  }
  return w;
}

}  // namespace minksum::detail
