// Exact floating-point expansions on the stack (internal): error-free transformations and the
// few expansion operations the exact predicates need (Shewchuk 1997, "Adaptive precision
// floating-point arithmetic and fast robust geometric predicates", sections 2.2-2.7).
//
// An expansion is an array of doubles, nonoverlapping and sorted by increasing magnitude, whose
// exact sum is the value it stands for; its sign is the sign of its last (largest) nonzero
// component. Every operation here is exact as long as no product underflows or overflows: the
// callers keep their inputs within [2^-300, 2^300] (or zero). The translation units that
// include this header are compiled with -ffp-contract=off: a multiply-add fused by the
// compiler would break the error-free transformations.
#pragma once

namespace minksum::detail::expansion {

/// a + b = x + y exactly, with x = fl(a + b) (Knuth's two-sum).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a, av = x - bv;
  y = (a - av) + (b - bv);
}

/// a - b = x + y exactly, with x = fl(a - b).
inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x, av = x + bv;
  y = (a - av) + (bv - b);
}

/// a = hi + lo with each half holding 26 bits (Dekker's split; |a| < 2^996).
inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;  // 2^27 + 1
  hi = c - (c - a);
  lo = a - hi;
}

/// a * b = x + y exactly, with x = fl(a * b) (Dekker's two-product, without FMA: the library's
/// baseline build has none).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  double ahi, alo, bhi, blo;
  split(a, ahi, alo);
  split(b, bhi, blo);
  y = alo * blo - (((x - ahi * bhi) - alo * bhi) - ahi * blo);
}

/// The exact 2 x 2 minor a * d - b * c as a 4-component expansion (Shewchuk's Two_Two_Diff).
inline void minor2(double a, double d, double b, double c, double* e) {
  double x1, x0, y1, y0;
  two_product(a, d, x1, x0);
  two_product(b, c, y1, y0);
  // (x1 + x0) - (y1 + y0), as Two_Two_Diff.
  double i, j, k, l;
  two_diff(x0, y0, i, e[0]);
  two_sum(x1, i, j, k);
  two_diff(k, y1, i, e[1]);
  two_sum(j, i, l, e[2]);
  e[3] = l;
}

/// h = e * b (e of n components; h has room for 2n), zero components dropped; returns the
/// length of h (Shewchuk's scale_expansion_zeroelim).
inline int scale(int n, const double* e, double b, double* h) {
  double q, hh, p1, p0, sum;
  int m = 0;
  two_product(e[0], b, q, hh);
  if (hh != 0) h[m++] = hh;
  for (int k = 1; k < n; ++k) {
    two_product(e[k], b, p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0) h[m++] = hh;
    const double t = p1 + sum;  // fast two-sum: |p1| >= |sum|
    hh = sum - (t - p1);
    q = t;
    if (hh != 0) h[m++] = hh;
  }
  if (q != 0 || m == 0) h[m++] = q;
  return m;
}

/// h = e + f (room for n + m components), zero components dropped; returns the length of h
/// (Shewchuk's fast_expansion_sum_zeroelim; needs round-to-nearest-even, the IEEE default).
inline int sum(int n, const double* e, int m, const double* f, double* h) {
  int ei = 0, fi = 0, out = 0;
  double q, qnew, hh;
  double enow = e[0], fnow = f[0];
  if ((fnow > enow) == (fnow > -enow)) {
    q = enow;
    enow = ++ei < n ? e[ei] : 0;
  } else {
    q = fnow;
    fnow = ++fi < m ? f[fi] : 0;
  }
  if (ei < n && fi < m) {
    if ((fnow > enow) == (fnow > -enow)) {
      qnew = enow + q, hh = q - (qnew - enow);
      enow = ++ei < n ? e[ei] : 0;
    } else {
      qnew = fnow + q, hh = q - (qnew - fnow);
      fnow = ++fi < m ? f[fi] : 0;
    }
    q = qnew;
    if (hh != 0) h[out++] = hh;
    while (ei < n && fi < m) {
      if ((fnow > enow) == (fnow > -enow)) {
        two_sum(q, enow, qnew, hh);
        enow = ++ei < n ? e[ei] : 0;
      } else {
        two_sum(q, fnow, qnew, hh);
        fnow = ++fi < m ? f[fi] : 0;
      }
      q = qnew;
      if (hh != 0) h[out++] = hh;
    }
  }
  while (ei < n) {
    two_sum(q, enow, qnew, hh);
    enow = ++ei < n ? e[ei] : 0;
    q = qnew;
    if (hh != 0) h[out++] = hh;
  }
  while (fi < m) {
    two_sum(q, fnow, qnew, hh);
    fnow = ++fi < m ? f[fi] : 0;
    q = qnew;
    if (hh != 0) h[out++] = hh;
  }
  if (q != 0 || out == 0) h[out++] = q;
  return out;
}

/// The sign of an expansion: of its largest component.
inline int sign(int n, const double* e) { return e[n - 1] > 0 ? 1 : e[n - 1] < 0 ? -1 : 0; }

/// The exact sign of the determinant of the rows p, q, r (each three doubles within
/// [2^-300, 2^300] or zero): p . (q x r) as a 24-component expansion.
inline int det3_sign(const double* p, const double* q, const double* r) {
  double m[3][4], s[3][8], t[16], u[24];
  minor2(q[1], r[2], q[2], r[1], m[0]);  // (q x r)_x
  minor2(q[2], r[0], q[0], r[2], m[1]);  // (q x r)_y
  minor2(q[0], r[1], q[1], r[0], m[2]);  // (q x r)_z
  const int a = scale(4, m[0], p[0], s[0]), b = scale(4, m[1], p[1], s[1]), c = scale(4, m[2], p[2], s[2]);
  const int ab = sum(a, s[0], b, s[1], t);
  return sign(sum(ab, t, c, s[2], u), u);
}

}  // namespace minksum::detail::expansion
