// The exact orientation of exact vectors (core/predicates.hpp: a double filter, a
// double-double stage, then the expansions) against rational arithmetic (GMP), on near-ties at
// every scale from 2^-40 to 2^-200 of the rows and on exact zeros.
#include <gtest/gtest.h>
#include <gmp.h>

#include <array>
#include <cmath>
#include <random>

#include "core/predicates.hpp"

namespace minksum {
namespace {

// A vector whose components are expansions of up to three terms on one grid: hi = m 2^-20,
// mid = m' 2^-s_mid, lo = m'' 2^-s_lo (|m| < 2^22), nonoverlapping (s_mid >= 42, s_lo >= s_mid + 23).
struct GridVector {
  std::array<std::array<double, 3>, 3> terms;  // per component: lo, mid, hi (increasing)
  std::array<int, 3> count;
  double sign = 1;
  std::array<std::array<double, 3>, 3> compact;  // the nonzero terms, increasing, as ExactVector reads them
  detail::ExactVector exact() {
    detail::ExactVector x{{compact[0].data(), compact[1].data(), compact[2].data()}, {0, 0, 0}, sign};
    for (int k = 0; k < 3; ++k) {
      int n = 0;
      for (double t : terms[k])
        if (t != 0) compact[k][n++] = t;
      x.count[k] = n;
    }
    return x;
  }
};

// The sign of det[p; q; r] in rationals, each component the exact sum of its terms times its sign.
int rational_orient(const GridVector* v[3]) {
  mpq_t c[3][3], t, det, prod;
  mpq_inits(t, det, prod, nullptr);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) {
      mpq_init(c[i][k]);
      for (double x : v[i]->terms[k]) {
        mpq_set_d(t, x * v[i]->sign);
        mpq_add(c[i][k], c[i][k], t);
      }
    }
  static const int perm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}};
  for (int p = 0; p < 6; ++p) {
    mpq_mul(prod, c[0][perm[p][0]], c[1][perm[p][1]]);
    mpq_mul(prod, prod, c[2][perm[p][2]]);
    (p < 3 ? mpq_add : mpq_sub)(det, det, prod);
  }
  const int s = mpq_sgn(det);
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) mpq_clear(c[i][k]);
  mpq_clears(t, det, prod, nullptr);
  return s;
}

TEST(Predicates, OrientExactEqualsRationalArithmeticOnNearTies) {
  std::mt19937_64 rng(20261129);
  std::uniform_int_distribution<long> big(-(1L << 20), 1L << 20), small(-1024, 1024);
  int decided[3] = {0, 0, 0};  // negative, zero, positive answers
  for (int n = 0; n < 20000; ++n) {
    const int s_mid = 42 + int(rng() % 40), s_lo = s_mid + 23 + int(rng() % 60);
    const auto grid = [&](long hi, long mid, long lo) {
      return std::array<double, 3>{std::ldexp(double(lo), -s_lo), std::ldexp(double(mid), -s_mid),
                                   std::ldexp(double(hi), -20)};
    };
    GridVector q, r, p;
    for (int k = 0; k < 3; ++k) {
      q.terms[k] = grid(big(rng), rng() % 2 ? big(rng) : 0, rng() % 2 ? big(rng) : 0);
      r.terms[k] = grid(big(rng), rng() % 2 ? big(rng) : 0, rng() % 2 ? big(rng) : 0);
    }
    // p = a q + b r (a, b in {-1, 1}: exact on the grid) plus a perturbation on the mid or the
    // lo grid, or none (an exact zero): its determinant is that of the perturbation alone.
    const double a = rng() % 2 ? 1 : -1, b = rng() % 2 ? 1 : -1;
    const int kind = int(rng() % 4);
    for (int k = 0; k < 3; ++k)
      for (int t = 0; t < 3; ++t) {
        p.terms[k][t] = a * q.terms[k][t] + b * r.terms[k][t];
        if ((kind == 1 && t == 1) || (kind == 2 && t == 0)) p.terms[k][t] += std::ldexp(double(small(rng)), t ? -s_mid : -s_lo);
      }
    if (kind == 3 && rng() % 2) p.terms = q.terms;  // a repeated row
    // Either vector may carry the sign -1 (a negated shape's normal).
    if (rng() % 4 == 0) q.sign = -1;
    const GridVector* rows[3] = {&p, &q, &r};
    const int expected = rational_orient(rows);
    ++decided[expected + 1];
    EXPECT_EQ(detail::orient_exact(p.exact(), q.exact(), r.exact()), expected) << "case " << n;
    EXPECT_EQ(detail::orient_exact(q.exact(), r.exact(), p.exact()), expected) << "case " << n << ", rotated";
    if (HasFailure()) break;
  }
  // Every answer occurs often (the cases reach all three stages).
  for (int s = 0; s < 3; ++s) EXPECT_GT(decided[s], 3000) << "answer " << s - 1;
}

}  // namespace
}  // namespace minksum
