// The exact orientation of exact vectors (core/predicates.hpp: a double filter, a
// double-double stage, then the expansions) against rational arithmetic (GMP), on near-ties at
// every scale from 2^-40 to 2^-200 of the rows and on exact zeros.
#include <gtest/gtest.h>
#include <gmp.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

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

// The rational value of component k of a vector to 106 bits minus that of an exact vector,
// and whether it is within the NearVector's bound (terms^2 2^-106 size).
bool within_bound(const detail::NearVector& n, const detail::ExactVector& x, int k) {
  mpq_t exact, near, t, bound;
  mpq_inits(exact, near, t, bound, nullptr);
  for (int i = 0; i < x.count[k]; ++i) mpq_set_d(t, x.terms[k][i] * x.sign), mpq_add(exact, exact, t);
  mpq_set_d(near, n.hi[k]), mpq_set_d(t, n.lo[k]), mpq_add(near, near, t);
  mpq_sub(t, near, exact), mpq_abs(t, t);
  mpq_set_d(bound, double(n.terms) * n.terms * std::ldexp(n.size, -106));
  const bool ok = mpq_cmp(t, bound) <= 0;
  mpq_clears(exact, near, t, bound, nullptr);
  return ok;
}

// A face's normal to 106 bits from its Newell products (near_gauss_normal, no expansions) is
// within its bound of the exact normal the predicates read (exact_gauss_normal), for rounded
// triangles and planar quads at scales from 2^-300 to 2^300; and near_apart, which tells a
// near-tie's faces apart without the expansions, never calls exactly parallel normals apart.
TEST(Predicates, NearGaussNormalIsWithinItsBoundOfTheExactNormal) {
  std::mt19937_64 rng(29112026);
  std::uniform_real_distribution<double> u(-1, 1);
  int checked = 0, apart = 0;
  for (int n = 0; n < 4000; ++n) {
    const double scale = std::ldexp(1.0, int(rng() % 600) - 300);
    std::vector<Eigen::Vector3d> p;
    for (int k = 0; k < 3; ++k) p.push_back(scale * Eigen::Vector3d(u(rng), u(rng), u(rng)));
    if (rng() % 2) p.push_back(p[2] + 0.75 * (p[0] - p[1]));  // a quad, planar up to rounding
    std::vector<int> loop(p.size());
    for (int k = 0; k < int(p.size()); ++k) loop[k] = k;
    std::vector<double> terms;
    int count[3], exponent = 0;
    detail::GaussKind kind;
    detail::gauss_normal(p, loop, terms, count, kind, exponent);
    if (kind != detail::GaussKind::OnDemand) continue;
    std::vector<double> px, py, pz;
    for (const auto& v : p) px.push_back(v.x()), py.push_back(v.y()), pz.push_back(v.z());
    double local[3 * detail::kMaxGaussTerms];
    const detail::ExactVector x =
        detail::exact_gauss_normal(loop.data(), int(p.size()), px.data(), py.data(), pz.data(), exponent, local);
    const detail::NearVector near =
        detail::near_gauss_normal(loop.data(), int(p.size()), px.data(), py.data(), pz.data(), exponent);
    ++checked;
    for (int k = 0; k < 3; ++k) EXPECT_TRUE(within_bound(near, x, k)) << "case " << n << ", component " << k;
    // The same normal, and twice it (exactly parallel): never apart. The normal with a
    // component moved by 2^-70 (a near-tie): apart.
    detail::NearVector twice = near, moved = near;
    for (int k = 0; k < 3; ++k) twice.hi[k] *= 2, twice.lo[k] *= 2;
    twice.size = 2 * near.size;
    moved.lo[0] += std::ldexp(std::abs(near.hi[0]) + std::abs(near.hi[1]) + std::abs(near.hi[2]), -70);
    EXPECT_FALSE(detail::near_apart(near, twice)) << "case " << n;
    const bool moved_apart = detail::near_apart(near, moved);
    apart += moved_apart;
    if (HasFailure()) break;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(apart, checked * 9 / 10);  // a 2^-70 tilt is told apart
}

}  // namespace
}  // namespace minksum
