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

// A growing expansion in two buffers used in turn, compressed (Shewchuk's compress: the same
// value in as few components as possible) when it would pass its capacity N. Compressed, it
// holds at most one component per 53 bits of exponent range: fewer than 45 in the range the
// callers keep (products of at most three terms within [2^-300, 2^300]).
template <int N>
struct Accumulator {
  double buf[2][N];
  double* e = buf[0];
  int n = 0;
  // Adds the expansion x of k <= N / 2 components.
  void add(const double* x, int k) {
    if (k == 0) return;
    if (n + k > N) compress();
    double* h = e == buf[0] ? buf[1] : buf[0];
    n = n ? expansion::sum(n, e, k, x, h) : (std::copy(x, x + k, h), k);
    e = h;
  }
  void compress() {
    if (n == 0) return;
    double g[N];
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
    if (q != 0 || top == 0) e[top++] = q;
    n = top;
    if (n == 1 && e[0] == 0) n = 0;
  }
  // The value rounded (the largest component dominates a compressed expansion), and whether
  // that is exact (one component).
  double value(bool& exact) {
    compress();
    exact &= n <= 1;
    return n ? e[n - 1] : 0.0;
  }
  // Adds the exact product of the expansions x (k terms) and y (m terms), one term of y at a
  // time (expansion::scale), times `sign`.
  void add_product(const double* x, int k, const double* y, int m, double sign) {
    double part[2 * kMaxProductTerms];
    for (int j = 0; j < m && k > 0; ++j) add(part, expansion::scale(k, x, sign * y[j], part));
  }
  static constexpr int kMaxProductTerms = N / 4;
};

}  // namespace

namespace {

// The exact minor x_a y_b - x_b y_a of two exact vectors into acc.
void exact_minor(const ExactVector& x, const ExactVector& y, int a, int b, Accumulator<256>& acc) {
  acc.n = 0;
  acc.add_product(x.terms[a], x.count[a], y.terms[b], y.count[b], x.sign * y.sign);
  acc.add_product(x.terms[b], x.count[b], y.terms[a], y.count[a], -x.sign * y.sign);
  acc.compress();
}

}  // namespace

namespace {

// A double-double: hi + lo.
struct Double2 {
  double hi, lo;
};

// x y in double-double, the lo x lo product dropped.
Double2 product2(const Double2& x, const Double2& y) {
  Double2 p;
  expansion::two_product(x.hi, y.hi, p.hi, p.lo);
  p.lo += x.hi * y.lo + x.lo * y.hi;
  return p;
}

}  // namespace

NearVector near_vector(const ExactVector& x) {
  NearVector out;
  out.size = 0, out.terms = 0;
  for (int k = 0; k < 3; ++k) {
    // (The errors of the two-sums added up apart: within count^2 2^-106 of the terms' magnitudes.)
    double s = 0, lo = 0, m = 0;
    for (int t = 0; t < x.count[k]; ++t) {
      double sum, e;
      expansion::two_sum(s, x.terms[k][t], sum, e);
      s = sum, lo += e;
      m += std::abs(x.terms[k][t]);
    }
    double hi, low;
    expansion::two_sum(s, lo, hi, low);
    out.hi[k] = x.sign * hi, out.lo[k] = x.sign * low;
    out.size = std::max(out.size, m);
    out.terms = std::max(out.terms, x.count[k]);
  }
  return out;
}

namespace {

// Component k of p x q in double-double, and its permanent |p_a q_b| + |p_b q_a|.
Double2 near_minor(const NearVector& p, const NearVector& q, int k, double& perm) {
  const int a = (k + 1) % 3, b = (k + 2) % 3;
  const Double2 x = product2({p.hi[a], p.lo[a]}, {q.hi[b], q.lo[b]}), y = product2({p.hi[b], p.lo[b]}, {q.hi[a], q.lo[a]});
  Double2 minor;
  expansion::two_diff(x.hi, y.hi, minor.hi, minor.lo);
  minor.lo += x.lo - y.lo;
  perm = std::abs(x.hi) + std::abs(y.hi);
  return minor;
}

}  // namespace

bool near_apart(const NearVector& p, const NearVector& q) {
  // As orient_near's bound, for two rows: each within terms^2 2^-106 of its size moves a minor
  // by at most 2 x 48^2 2^-106 size_p size_q (under 2^-93 of it), the evaluation errs by under
  // 2^-100 of its permanent.
  if (std::max(p.terms, q.terms) > 48) return false;
  for (int k = 0; k < 3; ++k) {
    double perm;
    const Double2 m = near_minor(p, q, k, perm);
    if (std::abs(m.hi + m.lo) > 0x1p-90 * (perm + p.size * q.size) + 0x1p-900) return true;
  }
  return false;
}

int orient_near(const NearVector& p, const NearVector& q, const NearVector& r) {
  // The rows are within terms^2 2^-106 of their magnitudes, which moves the determinant by at
  // most 18 terms^2 2^-106 size_p size_q size_r (under 2^-90 of it for terms <= 48); the
  // double-double evaluation below errs by under 61 x 2^-106 of the permanent (each product's
  // dropped lo x lo term and the roundings of its cross terms, then the sums'). 2^-90 of each,
  // and 2^-900 for what underflowed, bound both.
  if (std::max({p.terms, q.terms, r.terms}) > 48) return 0;
  double high[3], low = 0, perm = 0;
  for (int k = 0; k < 3; ++k) {
    double minor_perm;
    const Double2 term = product2({p.hi[k], p.lo[k]}, near_minor(q, r, k, minor_perm));
    high[k] = term.hi, low += term.lo;
    perm += std::abs(p.hi[k]) * minor_perm;
  }
  double s1, s2, e1, e2;
  expansion::two_sum(high[0], high[1], s1, e1);
  expansion::two_sum(s1, high[2], s2, e2);
  const double det = s2 + (low + e1 + e2);
  const double bound = 0x1p-90 * (perm + p.size * q.size * r.size) + 0x1p-900;
  return det > bound ? 1 : det < -bound ? -1 : 0;
}

int orient_exact(const ExactVector& p, const ExactVector& q, const ExactVector& r) {
  // Three stages. First a filter on the doubles nearest the exact components (each expansion's
  // terms summed from the smallest: within 2^-52 of its value), so each of the six products is
  // within 3 x 2^-52 of its own magnitude, on top of orient's 7.8e-16 of the permanent: a
  // near-tie of rounded normals (two cubes turned by 1e-13 rad) is decided here.
  const auto value = [](const ExactVector& x, int k) {
    double v = 0;
    for (int t = 0; t < x.count[k]; ++t) v += x.terms[k][t];
    return x.sign * v;
  };
  const Vector3d a(value(p, 0), value(p, 1), value(p, 2)), b(value(q, 0), value(q, 1), value(q, 2)),
      c(value(r, 0), value(r, 1), value(r, 2));
  const double approx = a.dot(b.cross(c));
  const double perm = a.cwiseAbs().dot(Vector3d(std::abs(b.y() * c.z()) + std::abs(b.z() * c.y()),
                                                std::abs(b.z() * c.x()) + std::abs(b.x() * c.z()),
                                                std::abs(b.x() * c.y()) + std::abs(b.y() * c.x())));
  if (std::abs(approx) > 2e-15 * perm) return approx > 0 ? 1 : -1;
  // Then the vectors to 106 bits: a near-tie of two copies of a rounded shape in one frame
  // (their normals differ by rounding, det ~ 1e-17) is decided there, in a fifth of the
  // expansions' time.
  if (const int s = orient_near(near_vector(p), near_vector(q), near_vector(r))) return s;
  return orient_expansions(p, q, r);
}

int orient_expansions(const ExactVector& p, const ExactVector& q, const ExactVector& r) {
  // det = sum_k p_k (q x r)_k, each minor compressed before it is scaled by p_k's terms.
  Accumulator<256> minor, det;
  for (int k = 0; k < 3; ++k) {
    if (p.count[k] == 0) continue;
    exact_minor(q, r, (k + 1) % 3, (k + 2) % 3, minor);
    if (minor.n > Accumulator<256>::kMaxProductTerms) return 0;  // (beyond the callers' range)
    det.add_product(minor.e, minor.n, p.terms[k], p.count[k], p.sign);
  }
  det.compress();
  return det.n ? expansion::sign(det.n, det.e) : 0;
}

bool collinear_exact(const ExactVector& p, const ExactVector& q) {
  Accumulator<256> minor;
  for (int k = 0; k < 3; ++k) {
    exact_minor(p, q, (k + 1) % 3, (k + 2) % 3, minor);
    if (minor.n != 0) return false;
  }
  return true;
}

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

namespace {

// The power of two that scales a loop (n points, point(k)) to a largest coordinate near 1:
// exact, and the Newell products neither underflow nor overflow (the direction is the same).
template <class Point>
int loop_exponent(int n, Point point) {
  double top = 0;
  for (int k = 0; k < n; ++k) top = std::max(top, point(k).cwiseAbs().maxCoeff());
  return top >= 0x1p-1000 ? exponent_of(top) : -1000;
}
template <class Point>
double loop_scale(int n, Point point) {
  const int e = loop_exponent(n, point);
  return power_of_two(-e / 2) * power_of_two(-e - (-e / 2));
}

// The exact Newell normal of the loop scaled by loop_scale, into acc[0..2]; false if a product
// underflowed (subnormal coordinates: then it is not exact).
template <class Point>
bool newell_expansions(int n, Point point, Accumulator<72> acc[3]) {
  const double scale = loop_scale(n, point);
  bool ok = true;
  for (int k = 0; k < n; ++k) {
    const Vector3d a = point(k) * scale, b = point(k + 1 < n ? k + 1 : 0) * scale;
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      double m[4];
      expansion::minor2(a[e], b[f], a[f], b[e], m);
      const double size = std::abs(a[e] * b[f]) + std::abs(a[f] * b[e]);
      if (size != 0 && size < 0x1p-900) ok = false;
      acc[d].add(m, 4);
    }
  }
  return ok;
}

// The same normal in double, and per component a bound on its error: 2 n + 2 roundings of the
// sum of its 2 n products' magnitudes; false where a product could have underflowed. It is
// summed relative to the first point: the sum over the loop of (p_k - p_0) x (p_k+1 - p_0) is
// Newell's normal for any loop (the p_0 terms cancel around it), and its products are of the
// face's size, not of its distance from the origin, which made the bound too loose to prove an
// icosahedron's faces (each difference's rounding is one more of the bound's roundings). The
// normal is scaled as newell_expansions scales it times 2^-shift.
template <class Point>
bool newell_double(int n, Point point, Vector3d& v, Vector3d& bound, int& shift) {
  const Vector3d o = point(0);
  const auto rel = [&](int k) { return Vector3d(point(k) - o); };
  const int e = loop_exponent(n, rel);
  const double scale = power_of_two(-e / 2) * power_of_two(-e - (-e / 2));
  shift = 2 * (e - loop_exponent(n, point));
  v = bound = Vector3d::Zero();
  double least = 1;  // the least nonzero scaled coordinate
  for (int k = 1; k + 1 < n; ++k) {
    const Vector3d a = rel(k) * scale, b = rel(k + 1) * scale;
    v += a.cross(b);
    for (int d = 0; d < 3; ++d) {
      const int x = (d + 1) % 3, y = (d + 2) % 3;
      bound[d] += std::abs(a[x] * b[y]) + std::abs(a[y] * b[x]);
      if (a[d] != 0) least = std::min(least, std::abs(a[d]));
      if (b[d] != 0) least = std::min(least, std::abs(b[d]));
    }
  }
  bound *= (2.0 * n + 2) * 0x1p-52;
  return least > 0x1p-440;  // (products of two such are above 2^-880: none underflowed)
}

// A loop of a std::vector of points.
struct LoopPoints {
  const std::vector<Vector3d>& points;
  const std::vector<int>& loop;
  Vector3d operator()(int k) const { return points[size_t(loop[size_t(k)])]; }
};

}  // namespace

Vector3d exact_newell(const std::vector<Vector3d>& points, const std::vector<int>& loop, bool* exact) {
  Vector3d v;
  if (small_integer_newell(points, loop, v)) {
    if (exact) *exact = true;
    return v;
  }
  Accumulator<72> n[3];
  bool ok = newell_expansions(int(loop.size()), LoopPoints{points, loop}, n);
  v = Vector3d(n[0].value(ok), n[1].value(ok), n[2].value(ok));
  if (exact) *exact = ok;
  return v;
}

namespace {

// The canonical direction of the exact vector n[0..2] (compressed expansions; `ok` false if
// they are not exact), and where it is not a double vector, its terms scaled alike (appended
// to `terms`, counts in count[k]); `exact` tells which.
template <int N>
Vector3d canonical_terms(Accumulator<N> n[3], bool ok, std::vector<double>& terms, int count[3], bool& exact) {
  count[0] = count[1] = count[2] = 0;
  exact = true;
  const Vector3d v(n[0].value(exact), n[1].value(exact), n[2].value(exact));
  exact = exact && ok;
  Vector3d w = canonical_direction(v, exact);
  // (A product that underflowed leaves no exact expansion: the rounded normal stands for it.
  // An axis, one nonzero component, is exactly a double direction: a cap or a box's face.)
  const int nonzero = (w.x() != 0) + (w.y() != 0) + (w.z() != 0);
  if (nonzero == 1 && !exact) w = canonical_direction(w, exact = true);
  if (exact || !ok || nonzero == 0) return w;
  // The expansions scaled as canonical_direction scaled v (a power of two, in two steps).
  const int e = exponent_of(v.cwiseAbs().maxCoeff());
  const double half = power_of_two(-e / 2), rest = power_of_two(-e - (-e / 2));
  for (int k = 0; k < 3; ++k) {
    if (w[k] == 0) continue;  // (flushed: below kTinyComponent)
    const int first = std::max(0, n[k].n - kMaxGaussTerms);  // the largest terms
    for (int t = first; t < n[k].n; ++t) {
      const double x = n[k].e[t] * half * rest;
      if (std::abs(x) >= kTinyComponent) terms.push_back(x), ++count[k];
    }
  }
  return w;
}

}  // namespace

Vector3d gauss_normal(const std::vector<Vector3d>& points, const std::vector<int>& loop, std::vector<double>& terms,
                      int count[3], GaussKind& kind, int& exponent) {
  count[0] = count[1] = count[2] = 0;
  Vector3d v;
  if (small_integer_newell(points, loop, v)) return kind = GaussKind::Exact, canonical_direction(v, true);
  // In double where its bound proves every sign (each component clear of its bound, or a sum of
  // zero products) and keeps the canonical vector within kRoundedNormal of the exact one:
  // no expansion until a predicate needs one (GaussKind::OnDemand).
  const LoopPoints point{points, loop};
  const int n = int(loop.size());
  Vector3d bound;
  int shift = 0;
  bool proven = newell_double(n, point, v, bound, shift) && v != Vector3d::Zero();
  for (int d = 0; d < 3; ++d) proven = proven && (bound[d] == 0 ? v[d] == 0 : std::abs(v[d]) > bound[d]);
  if (proven) {
    const int e = exponent_of(v.cwiseAbs().maxCoeff());
    exponent = e + shift;  // (the exact normal's, as newell_expansions scales it)
    const Vector3d w = canonical_direction(v, false);
    const int nonzero = (v.x() != 0) + (v.y() != 0) + (v.z() != 0);
    const bool flushed = (w.x() != 0) + (w.y() != 0) + (w.z() != 0) != nonzero;
    if (nonzero == 1) return kind = GaussKind::Exact, canonical_direction(w, true);  // an axis
    if (!flushed && bound.maxCoeff() * power_of_two(-e / 2) * power_of_two(-e - (-e / 2)) <= kRoundedNormal)
      return kind = GaussKind::OnDemand, w;
  }
  Accumulator<72> acc[3];
  const bool ok = newell_expansions(n, point, acc);
  bool exact = true;
  const Vector3d w = canonical_terms(acc, ok, terms, count, exact);
  kind = exact || count[0] + count[1] + count[2] == 0 ? GaussKind::Exact : GaussKind::Stored;
  return w;
}

ExactVector exact_gauss_normal(const int* loop, int n, const double* px, const double* py, const double* pz,
                               int exponent, double* local) {
  const auto point = [&](int k) { return Vector3d(px[loop[k]], py[loop[k]], pz[loop[k]]); };
  Accumulator<72> acc[3];
  newell_expansions(n, point, acc);
  const double half = power_of_two(-exponent / 2), rest = power_of_two(-exponent - (-exponent / 2));
  ExactVector out{{local, local + kMaxGaussTerms, local + 2 * kMaxGaussTerms}, {0, 0, 0}, 1.0};
  for (int k = 0; k < 3; ++k) {
    acc[k].compress();
    double* t = local + k * kMaxGaussTerms;
    for (int i = std::max(0, acc[k].n - kMaxGaussTerms); i < acc[k].n; ++i) {
      const double x = acc[k].e[i] * half * rest;
      if (std::abs(x) >= kTinyComponent) t[out.count[k]++] = x;
    }
  }
  return out;
}

NearVector near_gauss_normal(const int* loop, int n, const double* px, const double* py, const double* pz,
                             int exponent) {
  const auto point = [&](int k) { return Vector3d(px[loop[k]], py[loop[k]], pz[loop[k]]); };
  NearVector out{{0, 0, 0}, {0, 0, 0}, 0, 4 * n};
  // (Products that underflow err by 2^-1074 each: scaled up by at most 2^200, far below the
  // bound's 2^-900. A smaller normal is left to the expansions.)
  if (exponent < -200 || n > 12) return out.terms = 1 << 20, out;
  // The products newell_expansions sums (the loop scaled alike), summed by two-sum as
  // near_vector sums terms, then scaled as exact_gauss_normal scales its expansions.
  const double scale = loop_scale(n, point);
  double sum[3] = {0, 0, 0}, low[3] = {0, 0, 0}, size[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k) {
    const Vector3d a = point(k) * scale, b = point(k + 1 < n ? k + 1 : 0) * scale;
    for (int d = 0; d < 3; ++d) {
      const int e = (d + 1) % 3, f = (d + 2) % 3;
      double t[4];
      expansion::two_product(a[e], b[f], t[0], t[1]);
      expansion::two_product(a[f], b[e], t[2], t[3]);
      t[2] = -t[2], t[3] = -t[3];
      for (double x : t) {
        double s, err;
        expansion::two_sum(sum[d], x, s, err);
        sum[d] = s, low[d] += err, size[d] += std::abs(x);
      }
    }
  }
  const double half = power_of_two(-exponent / 2), rest = power_of_two(-exponent - (-exponent / 2));
  for (int d = 0; d < 3; ++d) {
    double hi, lo;
    expansion::two_sum(sum[d], low[d], hi, lo);
    out.hi[d] = hi * half * rest, out.lo[d] = lo * half * rest;
    out.size = std::max(out.size, size[d] * half * rest);
  }
  return out;
}

Vector3d gauss_side_normal(const Vector3d& p, const Vector3d& q, const ExactVector& n, std::vector<double>& terms,
                           int count[3], bool& exact) {
  // q - p exactly (a rounded difference and its error, per coordinate), the points scaled by a
  // power of two to a largest coordinate near 1 (the products neither underflow nor overflow).
  const double top = std::max(p.cwiseAbs().maxCoeff(), q.cwiseAbs().maxCoeff());
  const int e = top >= 0x1p-1000 ? exponent_of(top) : -1000;
  const double scale = power_of_two(-e / 2) * power_of_two(-e - (-e / 2));
  double d[3][2];
  int dn[3];
  for (int k = 0; k < 3; ++k) {
    double hi, lo;
    expansion::two_diff(q[k] * scale, p[k] * scale, hi, lo);
    dn[k] = 0;  // (increasing magnitude, zeros dropped)
    if (lo != 0) d[k][dn[k]++] = lo;
    if (hi != 0) d[k][dn[k]++] = hi;
  }
  Accumulator<256> c[3];  // d_a n_b - d_b n_a
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    c[k].add_product(n.terms[b], n.count[b], d[a], dn[a], n.sign);
    c[k].add_product(n.terms[a], n.count[a], d[b], dn[b], -n.sign);
    c[k].compress();
  }
  return canonical_terms(c, true, terms, count, exact);
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
