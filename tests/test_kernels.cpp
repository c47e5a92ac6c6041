// Every kernel, on every compiled and supported ISA, against its scalar double reference twin
// (brute force over corners and vertices), plus the topology tables and the ISA dispatch.
#include <gtest/gtest.h>
#include <minksum/kernels.hpp>
#include <minksum/mesh.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <set>

#include "checks.hpp"
#include "kernel_reference.hpp"
#include "simd/simd.hpp"
#include "sum/overlay.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;
constexpr Isa kIsas[] = {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512};
constexpr int kN = 1024;

Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  return tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3.2 * u(rng));
}

// The box (triangle) as the float kernel sees it: every input rounded to T.
template <class T>
Box rounded(const Box& b) {
  Box r;
  for (int d = 0; d < 3; ++d) {
    r.center[d] = T(b.center[d]);
    r.half_extents[d] = T(b.half_extents[d]);
    for (int a = 0; a < 3; ++a) r.rotation(d, a) = T(b.rotation(d, a));
  }
  return r;
}
template <class T>
Triangle rounded(const Triangle& t) {
  return {t.a.cast<T>().template cast<double>(), t.b.cast<T>().template cast<double>(),
          t.c.cast<T>().template cast<double>()};
}

// Brute-force support of the operand pair at the kernel's own normal n, its scale (the sum
// of the absolute terms, which bounds the rounding error) and its reach (the farthest point
// of the pair from the origin, |centre| + |half extents| or the farthest vertex, per operand).
struct Expected {
  double h, scale, reach = 0;
};

// Compares one kernel plane with the reference plane. Offsets are compared with the exact
// support at the kernel's own normal; corner codes except where n . u_k is a tie.
template <class T>
void compare(const KernelPlane& got, const KernelPlane& ref, const Expected& e, double ulps, double cross_len,
             const char* what, int p) {
  const double eps = std::numeric_limits<T>::epsilon();
  // Near the parallel threshold either decision is right (documented tie).
  if (std::abs(cross_len - double(kParallelThreshold<T>)) < 0.01 * kParallelThreshold<T>) return;
  ASSERT_EQ(got.valid, ref.valid) << what << " plane " << p;
  if (!got.valid) {
    EXPECT_EQ(got.normal, Vector3d::Zero()) << what << " plane " << p;
    return;
  }
  EXPECT_NEAR(got.normal.norm(), 1, 8 * eps) << what << " plane " << p;
  EXPECT_LE((got.normal - ref.normal).norm(), 16 * eps / cross_len) << what << " plane " << p;
  // The kernel's offset belongs to its normal before the components were rounded to T, each
  // by at most eps / 2 of the unit normal; the support moves by at most that times the reach
  // (the support function is Lipschitz with the farthest point's norm as its constant).
  EXPECT_LE(std::abs(got.offset - e.h), ulps * eps * e.scale + 0.5 * eps * e.reach)
      << what << " plane " << p << " offset " << got.offset << " vs " << e.h;
}

// Cap: the batch capacity; 1024 takes the kernel body for any row stride, 32 one compiled for
// that stride (see with_row_stride).
template <class T, int Cap = kN>
void check_box_box(Isa isa, const std::vector<std::pair<Box, Box>>& pairs, bool difference) {
  ASSERT_TRUE(force_isa(isa));
  auto A = std::make_unique<BoxBatch<T, Cap>>(), B = std::make_unique<BoxBatch<T, Cap>>();
  auto out = std::make_unique<BoxBoxPlanes<T, Cap>>();
  const double eps = std::numeric_limits<T>::epsilon();
  const double ulps = std::is_same_v<T, float> ? 8 : 1e-12 / eps;  // float 8 ulp; double 1e-12
  for (size_t base = 0; base < pairs.size(); base += Cap) {
    A->count = B->count = int(std::min<size_t>(Cap, pairs.size() - base));
    for (int k = 0; k < A->count; ++k) A->set(k, pairs[base + k].first), B->set(k, pairs[base + k].second);
    A->pad(), B->pad();
    box_box_planes(*A, *B, difference, *out);
    for (int k = 0; k < A->count; ++k) {
      const Box a = rounded<T>(pairs[base + k].first), b = rounded<T>(pairs[base + k].second);
      KernelPlane ref[30];
      detail::box_box_reference(a, b, difference, kParallelThreshold<T>, ref);
      for (int p = 0; p < 30; ++p) {
        const int axis = p % 15;
        KernelPlane got;
        got.normal = (p < 15 ? 1.0 : -1.0) * Vector3d(out->n[axis][0][k], out->n[axis][1][k], out->n[axis][2][k]);
        got.offset = out->offset[p][k];
        got.valid = out->valid[k] >> axis & 1;
        const double cross_len =
            axis < 6 ? 1 : a.rotation.col((axis - 6) / 3).cross(b.rotation.col((axis - 6) % 3)).norm();
        // Exact support of A (+) sB at the kernel's normal, and the scale of its terms.
        int ca, cb;
        const double s = difference ? -1 : 1;
        Expected e{detail::box_support_brute(a, got.normal, &ca) + detail::box_support_brute(b, s * got.normal, &cb),
                   std::abs(got.normal.dot(a.center)) + std::abs(got.normal.dot(b.center))};
        for (int d = 0; d < 3; ++d)
          e.scale += a.half_extents[d] * std::abs(got.normal.dot(a.rotation.col(d))) +
                     b.half_extents[d] * std::abs(got.normal.dot(b.rotation.col(d)));
        e.reach = a.center.norm() + a.half_extents.norm() + b.center.norm() + b.half_extents.norm();
        compare<T>(got, ref[p], e, ulps, cross_len, ("box-box pair " + std::to_string(base + k)).c_str(), p);
        if (!got.valid || testing::Test::HasFailure()) continue;
        // Corner codes from the sign bits, complemented on the opposite side; ties skipped.
        const int code = int(out->code[axis][k]), c = p < 15 ? code : 63 - code;
        for (int bit = 0; bit < 3; ++bit) {
          if (std::abs(got.normal.dot(a.rotation.col(bit))) > 64 * eps)
            EXPECT_EQ(c >> bit & 1, ca >> bit & 1) << "A corner, plane " << p;
          if (std::abs(got.normal.dot(b.rotation.col(bit))) > 64 * eps)
            EXPECT_EQ(c >> (3 + bit) & 1, cb >> bit & 1)
                << "B corner, plane " << p << " pair " << base + k << " of " << pairs.size();
        }
      }
      if (testing::Test::HasFailure()) return;
    }
  }
}

// The random pairs per pass of the reference comparisons: 50,000 (under the sanitizer, 5,000:
// the cost per case shrinks there, every kind of pair stays).
const int kPairs = test::scaled(50000, 5000);

// Random pairs, one in 16 tie-heavy (tests/ties: lattice boxes, every other one touching; exact
// in float too): parallel and perpendicular axes exactly, offsets of exact supports.
std::vector<std::pair<Box, Box>> random_box_pairs(int n, double spread, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::pair<Box, Box>> pairs;
  for (int k = 0; k < n; ++k) {
    pairs.emplace_back(tools::random_box(rng, spread, 2), tools::random_box(rng, spread, 2));
    if (k % 32 == 31)
      pairs.back() = test::ties::touching_boxes(rng);
    else if (k % 16 == 15)
      pairs.back() = {test::ties::lattice_box(rng, 2, 1), test::ties::lattice_box(rng, 2, 1)};
  }
  return pairs;
}

// The hard cases: aligned, tiny rotations down to 1e-12, 45 degrees, thin, far away.
std::vector<std::pair<Box, Box>> hard_box_pairs() {
  std::vector<std::pair<Box, Box>> pairs;
  const Vector3d axis = Vector3d(0.3, -0.5, 0.81).normalized();
  Box a, b;
  a.half_extents = Vector3d(1, 2, 3);
  pairs.emplace_back(a, b);  // aligned
  for (double angle : {1e-1, 1e-3, 1e-5, 1e-7, 1e-9, 1e-12}) {
    b.rotation = tools::axis_angle(axis, angle);
    pairs.emplace_back(a, b);
  }
  b.rotation = tools::axis_angle({0, 0, 1}, M_PI / 4);
  pairs.emplace_back(a, b);
  b.rotation = tools::axis_angle(axis, M_PI / 4);
  pairs.emplace_back(a, b);
  Box thin;
  thin.half_extents = Vector3d(1, 1, 1e-7);
  thin.rotation = tools::table1_rotation();
  pairs.emplace_back(a, thin);
  Box far = b;
  far.center = Vector3d(1e6, -1e6, 1e6);
  pairs.emplace_back(far, thin);
  return pairs;
}

class Kernels : public testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "NOT TESTED: this CPU lacks " << to_string(GetParam());
  }
  void TearDown() override { force_isa(Isa::Scalar), force_isa(best_); }
  Isa best_ = active_isa();
};

TEST_P(Kernels, BoxBoxFloatMatchesTheReference) {
  for (bool diff : {false, true}) {
    check_box_box<float>(GetParam(), random_box_pairs(kPairs, 5, 11 + diff), diff);
    check_box_box<float>(GetParam(), hard_box_pairs(), diff);
    check_box_box<float, 32>(GetParam(), random_box_pairs(5000, 5, 31 + diff), diff);
  }
}

TEST_P(Kernels, BoxBoxDoubleMatchesTheReference) {
  for (bool diff : {false, true}) {
    check_box_box<double>(GetParam(), random_box_pairs(kPairs, 5, 21 + diff), diff);
    check_box_box<double>(GetParam(), hard_box_pairs(), diff);
    check_box_box<double, 32>(GetParam(), random_box_pairs(5000, 5, 41 + diff), diff);
  }
}

template <class T>
void check_box_triangle(Isa isa, const std::vector<std::pair<Box, Triangle>>& pairs, bool difference) {
  ASSERT_TRUE(force_isa(isa));
  auto A = std::make_unique<BoxBatch<T, kN>>();
  auto tri = std::make_unique<TriangleBatch<T, kN>>();
  auto out = std::make_unique<BoxTrianglePlanes<T, kN>>();
  const double eps = std::numeric_limits<T>::epsilon();
  const double ulps = std::is_same_v<T, float> ? 8 : 1e-12 / eps;
  for (size_t base = 0; base < pairs.size(); base += kN) {
    A->count = tri->count = int(std::min<size_t>(kN, pairs.size() - base));
    for (int k = 0; k < A->count; ++k) A->set(k, pairs[base + k].first), tri->set(k, pairs[base + k].second);
    A->pad(), tri->pad();
    box_triangle_planes(*A, *tri, difference, *out);
    for (int k = 0; k < A->count; ++k) {
      const Box a = rounded<T>(pairs[base + k].first);
      const Triangle t = rounded<T>(pairs[base + k].second);
      KernelPlane ref[26];
      detail::box_triangle_reference(a, t, difference, kParallelThreshold<T>, ref);
      const bool degenerate = out->valid[k] >> 30 & 1;
      const Vector3d v[3] = {t.a, t.b, t.c};
      const Vector3d e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
      const double tri_len = e[0].cross(e[1]).norm() / (e[0].norm() * e[1].norm());
      for (int p = 0; p < 26; ++p) {
        const int axis = p % 13;
        KernelPlane got;
        got.normal = (p < 13 ? 1.0 : -1.0) * Vector3d(out->n[axis][0][k], out->n[axis][1][k], out->n[axis][2][k]);
        got.offset = out->offset[p][k];
        got.valid = !degenerate && (out->valid[k] >> axis & 1);
        double cross_len = axis < 3 ? 1 : tri_len;
        if (axis >= 4) {
          const Vector3d& ej = e[(axis - 4) % 3];
          cross_len = std::min(tri_len, a.rotation.col((axis - 4) / 3).cross(ej).norm() / ej.norm());
        }
        int ca;
        const double s = difference ? -1 : 1;
        double hv = -1e300;
        int vi = 0;
        for (int i = 0; i < 3; ++i)
          if (s * got.normal.dot(v[i]) > hv) hv = s * got.normal.dot(v[i]), vi = i;
        Expected ex{detail::box_support_brute(a, got.normal, &ca) + hv, std::abs(got.normal.dot(a.center))};
        for (int d = 0; d < 3; ++d) {
          ex.scale += a.half_extents[d] * std::abs(got.normal.dot(a.rotation.col(d)));
          ex.scale += std::abs(got.normal.dot(v[d]));
        }
        ex.reach = a.center.norm() + a.half_extents.norm() + std::max({v[0].norm(), v[1].norm(), v[2].norm()});
        compare<T>(got, ref[p], ex, ulps, cross_len, "box-triangle", p);
        if (!got.valid || testing::Test::HasFailure()) continue;
        const int code = int(out->code[p][k]);
        for (int bit = 0; bit < 3; ++bit)
          if (std::abs(got.normal.dot(a.rotation.col(bit))) > 64 * eps)
            EXPECT_EQ(code >> bit & 1, ca >> bit & 1) << "box corner, plane " << p;
        double second = -1e300;  // the runner-up vertex: a near tie makes the index ambiguous
        for (int i = 0; i < 3; ++i)
          if (i != vi) second = std::max(second, s * got.normal.dot(v[i]));
        if (hv - second > 64 * eps * ex.scale) EXPECT_EQ(code >> 3, vi) << "vertex, plane " << p;
      }
      if (testing::Test::HasFailure()) return;
    }
  }
}

std::vector<std::pair<Box, Triangle>> box_triangle_pairs(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::vector<std::pair<Box, Triangle>> pairs;
  for (int k = 0; k < n; ++k) {
    pairs.emplace_back(tools::random_box(rng, 3, 2), tools::random_triangle(rng, 3));
    if (k % 32 == 31)
      pairs.back() = test::ties::touching_box_triangle(rng);  // tie-heavy (tests/ties)
    else if (k % 16 == 15)
      pairs.back() = {test::ties::lattice_box(rng, 2, 1), test::ties::lattice_triangle(rng, 2, 1)};
  }
  // Hard cases: a triangle in a box face's plane, an axis-parallel edge, degenerate triangles.
  Box unit;
  pairs.emplace_back(unit, Triangle{{-0.5, -0.5, 1}, {0.7, -0.2, 1}, {0.1, 0.6, 1}});
  pairs.emplace_back(unit, Triangle{{0, 0, 0}, {1, 0, 0}, {0.3, 0.2, 0.9}});
  pairs.emplace_back(unit, Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});  // collinear
  pairs.emplace_back(unit, Triangle{{1, 2, 3}, {1, 2, 3}, {1, 2, 3}});  // a point
  Box far = unit;
  far.center = Vector3d(1e6, 1e6, -1e6);
  pairs.emplace_back(far, Triangle{{1e6, 1e6, -1e6}, {1e6 + 1, 1e6, -1e6}, {1e6, 1e6 + 1, -1e6 + 0.5}});
  return pairs;
}

TEST_P(Kernels, BoxTriangleMatchesTheReference) {
  for (bool diff : {false, true}) {
    check_box_triangle<float>(GetParam(), box_triangle_pairs(kPairs, 31 + diff), diff);
    check_box_triangle<double>(GetParam(), box_triangle_pairs(kPairs, 41 + diff), diff);
  }
}

TEST_P(Kernels, DegenerateTrianglesAreFlaggedNotNaN) {
  ASSERT_TRUE(force_isa(GetParam()));
  auto A = std::make_unique<BoxBatch<float, 16>>();
  auto tri = std::make_unique<TriangleBatch<float, 16>>();
  auto out = std::make_unique<BoxTrianglePlanes<float, 16>>();
  A->count = tri->count = 2;
  A->set(0, Box{}), A->set(1, Box{});
  tri->set(0, Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}});
  tri->set(1, Triangle{{5, 5, 5}, {5, 5, 5}, {5, 5, 5}});
  A->pad(), tri->pad();
  box_triangle_planes(*A, *tri, false, *out);
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(out->valid[k] >> 30 & 1);
    for (int p = 0; p < 26; ++p) EXPECT_TRUE(std::isfinite(out->offset[p][k]));
    for (int p = 0; p < 13; ++p)
      for (int d = 0; d < 3; ++d) EXPECT_TRUE(std::isfinite(out->n[p][d][k]));
  }
}

// A triangle with an edge under 1e-19 beside edges of 237 (fuzz_kernels, the CI smoke of
// 6793a52): the float squares of that edge are subnormal or 0, and the hardware rsqrt
// estimate read a subnormal squared cross length as 0, so the triangle's normal and its
// offsets were NaN on every SIMD ISA. Every plane must be finite, and every valid one a support
// plane of the box and the triangle (brute force over the corners).
TEST_P(Kernels, AnEdgeBelowFloatRangeGivesFinitePlanes) {
  ASSERT_TRUE(force_isa(GetParam()));
  auto A = std::make_unique<BoxBatch<float, 16>>();
  auto tri = std::make_unique<TriangleBatch<float, 16>>();
  auto out = std::make_unique<BoxTrianglePlanes<float, 16>>();
  Box box;
  box.center = box.half_extents = Eigen::Vector3d::Constant(237.5);
  box.rotation << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  const double tiny[4] = {0x1.bp-76, 1e-20, 1e-30, 1e-40};
  Triangle t[12];
  A->count = tri->count = 12;
  for (int k = 0; k < 12; ++k) {
    Eigen::Vector3d edge = Eigen::Vector3d::Zero();
    edge[k % 3] = tiny[k / 3];
    t[k] = Triangle{Eigen::Vector3d::Zero(), edge, Eigen::Vector3d(237.5, 237.5 - k, 237.5 + k)};
    A->set(k, box), tri->set(k, t[k]);
  }
  A->pad(), tri->pad();
  box_triangle_planes(*A, *tri, false, *out);
  // 8 float ulps of the operands' size, as fuzz_kernels allows (the edges' float rounding).
  const double bound = 8 * std::numeric_limits<float>::epsilon() * 3 * 712.5;
  for (int k = 0; k < 12; ++k) {
    const Eigen::Vector3d v[3] = {t[k].a.cast<float>().cast<double>(), t[k].b.cast<float>().cast<double>(),
                                  t[k].c.cast<float>().cast<double>()};
    for (int p = 0; p < 26; ++p) {
      const int axis = p % 13;
      const Eigen::Vector3d n =
          (p < 13 ? 1.0 : -1.0) * Eigen::Vector3d(out->n[axis][0][k], out->n[axis][1][k], out->n[axis][2][k]);
      ASSERT_TRUE(std::isfinite(out->offset[p][k]) && n.allFinite()) << "lane " << k << " plane " << p;
      if (out->valid[k] >> 30 & 1 || !(out->valid[k] >> axis & 1)) continue;
      EXPECT_NEAR(n.norm(), 1, 1e-6) << "lane " << k << " plane " << p;
      int code;
      const double top = detail::box_support_brute(box, n, &code) + std::max({n.dot(v[0]), n.dot(v[1]), n.dot(v[2])});
      EXPECT_NEAR(out->offset[p][k], top, bound) << "lane " << k << " plane " << p;
    }
  }
}

template <class T>
void check_support(Isa isa) {
  ASSERT_TRUE(force_isa(isa));
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  const double eps = std::numeric_limits<T>::epsilon();
  constexpr int K = 10000;  // 10 vertex sets x 10,000 directions = 100,000 problems
  for (int n : {1, 3, 7, 16, 17, 31, 64, 100, 1000, 4099}) {
    std::vector<T> x(n), y(n), z(n), dx(K), dy(K), dz(K), best(K);
    std::vector<int> arg(K);
    for (int k = 0; k < n; ++k) x[k] = T(u(rng)), y[k] = T(u(rng)), z[k] = T(u(rng));
    for (int q = 0; q < K; ++q) dx[q] = T(u(rng)), dy[q] = T(u(rng)), dz[q] = T(u(rng));
    support_push(x.data(), y.data(), z.data(), n, dx.data(), dy.data(), dz.data(), K, best.data(), arg.data());
    for (int q = 0; q < K; ++q) {
      double top = -1e300;
      for (int k = 0; k < n; ++k)
        top = std::max(top, double(dx[q]) * x[k] + double(dy[q]) * y[k] + double(dz[q]) * z[k]);
      ASSERT_NEAR(best[q], top, 8 * eps) << "n " << n;
      ASSERT_GE(arg[q], 0);
      ASSERT_LT(arg[q], n);
      const double at = double(dx[q]) * x[arg[q]] + double(dy[q]) * y[arg[q]] + double(dz[q]) * z[arg[q]];
      ASSERT_NEAR(at, top, 8 * eps) << "n " << n;
    }
  }
  // Ties go to the first index: every vertex equal, in every lane and in the tail.
  for (int n : {1, 5, 16, 33}) {
    std::vector<T> x(n, T(0.5)), y(n, T(-0.25)), z(n, T(2));
    const T d[3] = {T(0.3), T(-0.7), T(0.1)};
    T top;
    int at = -1;
    support_push(x.data(), y.data(), z.data(), n, d, d + 1, d + 2, 1, &top, &at);
    EXPECT_EQ(at, 0) << "n " << n;
  }
  // Integer vertices and directions (every product exact): the cube's corners twice over, so
  // that every direction ties; 33 directions cover whole blocks of lanes and the leftovers.
  std::vector<T> x, y, z, dx, dy, dz;
  for (int copy = 0; copy < 2; ++copy)
    for (int c = 0; c < 8; ++c)
      x.push_back(T(c & 1 ? 1 : -1)), y.push_back(T(c & 2 ? 1 : -1)), z.push_back(T(c & 4 ? 1 : -1));
  const int n = int(x.size()), m = 33;
  for (int q = 0; q < m; ++q)
    dx.push_back(T(q % 3 - 1)), dy.push_back(T(q / 3 % 3 - 1)), dz.push_back(T(q / 9 % 3 - 1));
  std::vector<T> best(m);
  std::vector<int> arg(m);
  support_push(x.data(), y.data(), z.data(), n, dx.data(), dy.data(), dz.data(), m, best.data(), arg.data());
  for (int q = 0; q < m; ++q) {
    int first = 0;
    for (int k = 1; k < n; ++k)
      if (dx[q] * x[k] + dy[q] * y[k] + dz[q] * z[k] > dx[q] * x[first] + dy[q] * y[first] + dz[q] * z[first])
        first = k;
    EXPECT_EQ(arg[q], first) << "direction " << q;
    EXPECT_EQ(best[q], dx[q] * x[first] + dy[q] * y[first] + dz[q] * z[first]) << "direction " << q;
  }
}

TEST_P(Kernels, SupportPushMatchesBruteForce) {
  check_support<float>(GetParam());
  check_support<double>(GetParam());
}

// The small overlay's sign tables (detail::side_masks) against the signs computed one by one
// in long double: random vectors (n lanes of 1 ... 64, whole and partial registers) with a
// filter well clear of every product; then integer vectors, whose products are exact, with a
// product at the filter's edge or exactly 0 (not certain: false) in the last query only.
TEST_P(Kernels, SideMasksMatchBruteForce) {
  ASSERT_TRUE(force_isa(GetParam()));
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int n : {1, 3, 8, 9, 30, 63, 64}) {
    alignas(64) double px[64] = {}, py[64] = {}, pz[64] = {};
    for (int i = 0; i < n; ++i) px[i] = u(rng), py[i] = u(rng), pz[i] = u(rng);
    constexpr int m = 40;
    double gx[m], gy[m], gz[m];
    std::uint64_t out[m];
    for (int j = 0; j < m; ++j) gx[j] = u(rng), gy[j] = u(rng), gz[j] = u(rng);
    const double filter = 1e-9;  // (no random product comes within 1e-9 of 0 or of the filter)
    ASSERT_TRUE(detail::side_masks(px, py, pz, n, gx, gy, gz, m, filter, out)) << "n " << n;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < n; ++i) {
        const long double v = (long double)px[i] * gx[j] + (long double)py[i] * gy[j] + (long double)pz[i] * gz[j];
        ASSERT_EQ(bool(out[j] >> i & 1), v > filter) << "n " << n << " lane " << i << " query " << j;
      }
    for (int j = 0; j < m; ++j) ASSERT_EQ(n < 64 ? out[j] >> n : 0, 0u) << "bits past lane n - 1, n " << n;
  }
  // Integer vectors: p_i = (i, 1, -2); g = (1, a, b) gives i + a - 2 b, exact.
  alignas(64) double px[64] = {}, py[64] = {}, pz[64] = {};
  const int n = 20;
  for (int i = 0; i < n; ++i) px[i] = i + 1, py[i] = 1, pz[i] = -2;
  // Products i + 1 - 10.5, i + 4 and (the last) i - 4, which is 0 at i = 4.
  const double gx[3] = {1, 1, 1}, gy[3] = {0, 3, 3}, gz[3] = {5.25, 0, 4};
  std::uint64_t out[3];
  EXPECT_FALSE(detail::side_masks(px, py, pz, n, gx, gy, gz, 3, 0.25, out));
  EXPECT_TRUE(detail::side_masks(px, py, pz, n, gx, gy, gz, 2, 0.25, out));
  for (int i = 0; i < n; ++i) {
    EXPECT_EQ(bool(out[0] >> i & 1), i + 1 - 10.5 > 0) << i;
    EXPECT_EQ(bool(out[1] >> i & 1), true) << i;
  }
  const double hx[1] = {1}, hy[1] = {0}, hz[1] = {0};  // products 1 ... 20: 1 at the filter's edge
  EXPECT_FALSE(detail::side_masks(px, py, pz, n, hx, hy, hz, 1, 1.0, out));
  EXPECT_TRUE(detail::side_masks(px, py, pz, n, hx, hy, hz, 1, 0.999, out));
  EXPECT_EQ(out[0], (std::uint64_t(1) << n) - 1);
}

// Triangle pairs for the batched distance: random ones (apart and meeting), near-parallel
// ones (1e-3 ... 1e-9 rad) just apart, coplanar ones, small triangles at 1e6, flat ones
// (collinear corners, a point), piercing ones, pairs spanning `huge` and `tiny` (beyond the
// kernel's range: the scalar path's lanes), and pairs just inside the range's ends (`high`,
// `low`), where products of six coordinates would overflow or underflow.
std::vector<std::pair<Triangle, Triangle>> triangle_pairs(int n, unsigned seed, double huge, double tiny, double high,
                                                          double low) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto vec = [&] { return Vector3d(u(rng), u(rng), u(rng)); };
  std::vector<std::pair<Triangle, Triangle>> out;
  for (int k = 0; out.size() < size_t(n); ++k) {
    Triangle s{vec(), vec(), vec()}, t{vec(), vec(), vec()};
    const Vector3d shift = vec() * (k % 3);
    t = {t.a + shift, t.b + shift, t.c + shift};
    switch (k % 9) {
      case 1: {  // near-parallel: t is s turned by a tiny angle and lifted along its normal
        const Eigen::Matrix3d R = tools::axis_angle(vec(), std::pow(10.0, -3 - k % 7));
        const Vector3d n = (s.b - s.a).cross(s.c - s.a).normalized() * 1e-3 * (1 + u(rng));
        t = {R * s.a + n + 0.3 * vec(), R * s.b + n, R * s.c + n};
        break;
      }
      case 2: {  // coplanar
        const Vector3d e = 0.5 * (s.b - s.a) + 0.3 * (s.c - s.a);
        t = {s.a + e, s.b + 2 * e, s.c + e};
        break;
      }
      case 3:  // small triangles far out
        for (Triangle* x : {&s, &t}) {
          const Vector3d far(1e6, -2e6, 3e6);
          *x = {far + 1e-3 * x->a, far + 1e-3 * x->b, far + 1e-3 * x->c};
        }
        break;
      case 4:  // flat: collinear corners, and a point
        s.c = s.a + 0.5 * (s.b - s.a);
        if (k % 2) t.b = t.c = t.a;
        break;
      case 5: {  // an edge of t through s's interior
        const Vector3d in = (s.a + s.b + s.c) / 3, n = (s.b - s.a).cross(s.c - s.a);
        t.a = in + 0.5 * n, t.b = in - 0.5 * n + 0.01 * vec();
        break;
      }
      case 6:  // spanning far beyond the kernel's range, and far below it
        for (Triangle* x : {&s, &t}) {
          const double f = k % 2 ? huge : tiny;
          *x = {f * x->a, f * x->b, f * x->c};
        }
        break;
      case 7:  // just inside the kernel's range (the span is at most twice the scale)
        for (Triangle* x : {&s, &t}) {
          const double f = k % 2 ? high / 2 : low;
          *x = {f * x->a, f * x->b, f * x->c};
        }
        break;
      default:
        break;
    }
    out.emplace_back(s, t);
  }
  return out;
}

// Distance of point p from triangle t (the scalar path with a point as the other triangle).
double off(const Triangle& t, const Vector3d& p) {
  const Vector3d a[3] = {t.a, t.b, t.c}, q[3] = {p, p, p};
  Vector3d x, y;
  return triangle_distance(a, q, x, y);
}

template <class T>
void check_triangle_distance(Isa isa, unsigned seed) {
  ASSERT_TRUE(force_isa(isa));
  const bool single = std::is_same_v<T, float>;
  // (The kernel's range is [kTriLow, kTriHigh] in simd/triangle_distance.hpp.)
  const auto pairs = triangle_pairs(kN, seed, single ? 1e30 : 1e80, single ? 1e-30 : 1e-70, single ? 1e6 : 1e60,
                                    single ? 1e-6 : 1e-60);
  auto S = std::make_unique<TriangleBatch<T, kN>>(), U = std::make_unique<TriangleBatch<T, kN>>();
  auto out = std::make_unique<TriangleDistances<T, kN>>();
  for (int k = 0; k < kN; ++k) S->set(k, pairs[k].first), U->set(k, pairs[k].second);
  S->count = U->count = kN;
  triangle_distance(*S, *U, *out);
  // Relative error against the scalar double path on the same (rounded) corners: a few ulps
  // of the pair's span, more in float, where near-parallel edges lose more.
  const double eps = std::is_same_v<T, float> ? 2e-4 : 1e-12;
  int zero = 0;
  for (int k = 0; k < kN; ++k) {
    Triangle s, t;
    for (auto [batch, tri] : {std::pair{S.get(), &s}, std::pair{U.get(), &t}})
      for (int i = 0; i < 3; ++i)
        for (int d = 0; d < 3; ++d) (i == 0 ? tri->a : i == 1 ? tri->b : tri->c)[d] = double(batch->v[i][d][k]);
    const Vector3d a[3] = {s.a, s.b, s.c}, b[3] = {t.a, t.b, t.c};
    Vector3d pa, pb;
    const double want = triangle_distance(a, b, pa, pb);
    double span = 0;
    for (const Vector3d* v : {&s.b, &s.c, &t.a, &t.b, &t.c}) span = std::max(span, (*v - s.a).cwiseAbs().maxCoeff());
    const double got = double(out->distance[k]);
    ASSERT_NEAR(got, want, eps * span) << "lane " << k << std::setprecision(17) << " s " << s.a.transpose() << " / "
                                       << s.b.transpose() << " / " << s.c.transpose() << " t " << t.a.transpose()
                                       << " / " << t.b.transpose() << " / " << t.c.transpose();
    // The points are absolute: also a few ulps of the corner's coordinates.
    const double at = 4 * eps * span + 8 * std::numeric_limits<T>::epsilon() * s.a.cwiseAbs().maxCoeff();
    const Vector3d ps(out->point_s[0][k], out->point_s[1][k], out->point_s[2][k]);
    const Vector3d pt(out->point_t[0][k], out->point_t[1][k], out->point_t[2][k]);
    ASSERT_NEAR((ps - pt).norm(), got, 2 * at) << "lane " << k;
    ASSERT_LE(off(s, ps), at) << "lane " << k;
    ASSERT_LE(off(t, pt), at) << "lane " << k;
    zero += want == 0;
  }
  EXPECT_GT(zero, kN / 20);  // meeting pairs were part of the test
}

// The whole-polytope kernel against the hull of the 64 pairwise corner sums, by brute force (no
// hull code: the exact hull of the rounded corners would split the faces that rounding bent). In
// general position: the corners are the boxes' corners, the 30 loops lie on their planes,
// counter-clockwise from outside, close into a 2-manifold of 32 vertices and 60 edges, and every
// plane supports the 64 sums; such a surface is their hull. Returns the general lanes.
template <class T>
int check_box_box_sum(Isa isa, const std::vector<std::pair<Box, Box>>& pairs) {
  EXPECT_TRUE(force_isa(isa));
  constexpr int N = 64;
  auto A = std::make_unique<BoxBatch<T, N>>(), B = std::make_unique<BoxBatch<T, N>>();
  auto out = std::make_unique<BoxBoxSum<T, N>>();
  const double eps = std::is_same_v<T, float> ? 1e-6 : 1e-14;
  int general = 0;
  for (size_t base = 0; base < pairs.size(); base += N) {
    const int n = int(std::min(pairs.size() - base, size_t(N)));
    for (int k = 0; k < n; ++k) A->set(k, pairs[base + k].first), B->set(k, pairs[base + k].second);
    A->count = B->count = n;
    A->pad(), B->pad();
    box_box_sum(*A, *B, *out);
    for (int k = 0; k < n; ++k) {
      const std::string what = std::string(to_string(isa)) + " pair " + std::to_string(base + k);
      const Box a = rounded<T>(pairs[base + k].first), b = rounded<T>(pairs[base + k].second);
      const double size =
          std::max({a.center.norm(), b.center.norm(), 1.0}) + a.half_extents.sum() + b.half_extents.sum();
      const double tol = 64 * eps * size;
      std::vector<Vector3d> sums;
      for (int i = 0; i < 8; ++i)
        for (int j = 0; j < 8; ++j) sums.push_back(box_corner(a, i) + box_corner(b, j));
      const auto corner = [&](const T(&c)[8][3][N], int i) { return Vector3d(c[i][0][k], c[i][1][k], c[i][2][k]); };
      for (int i = 0; i < 8; ++i) {
        EXPECT_LE((corner(out->corner_a, i) - box_corner(a, i)).norm(), tol) << what;
        EXPECT_LE((corner(out->corner_b, i) - box_corner(b, i)).norm(), tol) << what;
      }
      if (!out->general[k]) continue;
      ++general;
      // The hull of the pairwise sums, by brute force: a closed surface of convex facets whose
      // vertices are pairwise sums and whose planes all support the 64 sums is their hull.
      std::set<int> got;
      std::map<std::pair<int, int>, int> directed;
      for (int p = 0; p < 30; ++p) {
        const int q = p % 15;
        const Vector3d nrm =
            (p < 15 ? 1.0 : -1.0) * Vector3d(out->planes.n[q][0][k], out->planes.n[q][1][k], out->planes.n[q][2][k]);
        int v[4];
        Vector3d P[4];
        for (int m = 0; m < 4; ++m) {
          v[m] = int(out->loop[p][k] >> (6 * m) & 63);
          P[m] = corner(out->corner_a, v[m] & 7) + corner(out->corner_b, v[m] >> 3);
          EXPECT_NEAR(nrm.dot(P[m]), double(out->planes.offset[p][k]), tol) << what << " facet " << p;
          got.insert(v[m]);
        }
        double support = -std::numeric_limits<double>::infinity();
        for (const auto& x : sums) support = std::max(support, nrm.dot(x));
        EXPECT_NEAR(support, double(out->planes.offset[p][k]), tol)
            << what << " facet " << p << " does not support the sums";
        for (int m = 0; m < 4; ++m) {
          ++directed[{v[m], v[(m + 1) % 4]}];
          EXPECT_GT((P[(m + 1) % 4] - P[m]).cross(P[(m + 2) % 4] - P[(m + 1) % 4]).dot(nrm), 0)
              << what << " facet " << p;
        }
      }
      EXPECT_EQ(got.size(), 32u) << what;
      EXPECT_EQ(directed.size(), 120u) << what;  // 60 edges, each once each way
      for (const auto& [e, count] : directed) EXPECT_TRUE(count == 1 && directed.count({e.second, e.first})) << what;
      if (testing::Test::HasFailure()) return general;
    }
  }
  return general;
}

TEST_P(Kernels, BoxBoxSumIsTheHullOfThePairwiseSums) {
  const auto random = random_box_pairs(2000, 5, 41);
  for (int t = 0; t < 2; ++t) {
    const int general =
        t ? check_box_box_sum<float>(GetParam(), random) : check_box_box_sum<double>(GetParam(), random);
    EXPECT_GT(general, 1780) << "random pairs are in general position (all but the 125 lattice pairs)";
  }
  // Aligned boxes, and a cube turned about one of its axes (three coplanar edges), are not in
  // general position; turned about a generic axis, they are (down to the threshold).
  Box a, b;
  a.half_extents = Vector3d(1, 2, 3);
  std::vector<std::pair<Box, Box>> special{{a, b}};
  b.rotation = tools::axis_angle({0, 0, 1}, 0.5);
  special.emplace_back(a, b);
  b.rotation = tools::axis_angle(Vector3d(0.3, -0.5, 0.81).normalized(), 0.5);
  special.emplace_back(a, b);
  b.rotation = tools::table1_rotation();
  special.emplace_back(a, b);
  EXPECT_EQ(check_box_box_sum<double>(GetParam(), special), 2);
  EXPECT_EQ(check_box_box_sum<float>(GetParam(), special), 2);
  check_box_box_sum<double>(GetParam(), hard_box_pairs());
  check_box_box_sum<float>(GetParam(), hard_box_pairs());
}

// The box-box kernel body compiled for a fixed row stride (capacity 32) and the one for any
// stride (capacity 48) give the same bits, sum and difference.
template <class T>
void check_row_strides(Isa isa) {
  ASSERT_TRUE(force_isa(isa));
  auto A = std::make_unique<BoxBatch<T, 32>>(), B = std::make_unique<BoxBatch<T, 32>>();
  auto A48 = std::make_unique<BoxBatch<T, 48>>(), B48 = std::make_unique<BoxBatch<T, 48>>();
  auto out = std::make_unique<BoxBoxSum<T, 32>>();
  auto out48 = std::make_unique<BoxBoxSum<T, 48>>();
  const auto pairs = random_box_pairs(32, 5, 51);
  for (int k = 0; k < 32; ++k) {
    A->set(k, pairs[k].first), B->set(k, pairs[k].second);
    A48->set(k, pairs[k].first), B48->set(k, pairs[k].second);
  }
  A->count = B->count = A48->count = B48->count = 32;
  A48->pad(), B48->pad();
  box_box_sum(*A, *B, *out);
  box_box_sum(*A48, *B48, *out48);
  for (int k = 0; k < 32; ++k) {
    ASSERT_EQ(out->general[k], out48->general[k]);
    ASSERT_EQ(out->planes.valid[k], out48->planes.valid[k]);
    for (int p = 0; p < 30; ++p) {
      ASSERT_EQ(out->planes.offset[p][k], out48->planes.offset[p][k]) << "plane " << p << " lane " << k;
      ASSERT_EQ(out->loop[p][k], out48->loop[p][k]);
    }
    for (int p = 0; p < 15; ++p) {
      ASSERT_EQ(out->planes.code[p][k], out48->planes.code[p][k]);
      for (int d = 0; d < 3; ++d) ASSERT_EQ(out->planes.n[p][d][k], out48->planes.n[p][d][k]);
    }
    for (int i = 0; i < 8; ++i)
      for (int d = 0; d < 3; ++d) {
        ASSERT_EQ(out->corner_a[i][d][k], out48->corner_a[i][d][k]);
        ASSERT_EQ(out->corner_b[i][d][k], out48->corner_b[i][d][k]);
      }
  }
  box_box_planes(*A, *B, true, out->planes);
  box_box_planes(*A48, *B48, true, out48->planes);
  for (int k = 0; k < 32; ++k)
    for (int p = 0; p < 30; ++p) ASSERT_EQ(out->planes.offset[p][k], out48->planes.offset[p][k]);
}

TEST_P(Kernels, BoxBoxSameBitsAtEveryRowStride) {
  check_row_strides<float>(GetParam());
  check_row_strides<double>(GetParam());
}

TEST_P(Kernels, TriangleDistanceMatchesTheScalarPath) {
  for (unsigned seed = 31; seed < 39; ++seed) {  // 8 x 1024 pairs in each type
    check_triangle_distance<double>(GetParam(), seed);
    check_triangle_distance<float>(GetParam(), seed);
  }
}

INSTANTIATE_TEST_SUITE_P(Isa, Kernels, testing::ValuesIn(kIsas),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// Every ISA's kernel table has every entry set: make_table fills it by name, so an entry
// left out would stay null and crash only when that kernel is first called on that ISA.
TEST(Kernels, EveryTableIsComplete) {
  using detail::KernelTable;
  const std::pair<const KernelTable*, const char*> tables[] = {{&detail::kTableScalar, "scalar"},
                                                               {&detail::kTableSse4_2, "sse4_2"},
                                                               {&detail::kTableAvx2, "avx2"},
                                                               {&detail::kTableAvx512, "avx512"}};
  for (const auto& [t, name] : tables) {
    const bool set[] = {t->box_box_f != nullptr,
                        t->box_box_d != nullptr,
                        t->box_tri_f != nullptr,
                        t->box_tri_d != nullptr,
                        t->support_f != nullptr,
                        t->support_d != nullptr,
                        t->box_box_single_d != nullptr,
                        t->box_box_proximity_f != nullptr,
                        t->box_box_proximity_d != nullptr,
                        t->box_box_separation_f != nullptr,
                        t->box_box_separation_d != nullptr,
                        t->box_triangle_overlap_f != nullptr,
                        t->box_triangle_overlap_d != nullptr,
                        t->box_pair_d != nullptr,
                        t->tri_tri_f != nullptr,
                        t->tri_tri_d != nullptr,
                        t->side_masks_d != nullptr};
    static_assert(sizeof(set) == 17 && sizeof(KernelTable) == 17 * sizeof(void (*)()),
                  "a new kernel table entry needs its check here");
    for (size_t k = 0; k < sizeof(set); ++k) EXPECT_TRUE(set[k]) << name << " entry " << k;
  }
}

// The ISA suites above skip an ISA the CPU lacks; a skip must not hide one it has. The CPU's
// own answer (CPUID through the compiler's builtin, independent of xsimd's detection) must
// agree with isa_supported for every ISA, and the start-up choice must be the best of them.
TEST(Kernels, NoIsaTheCpuHasIsSkipped) {
  __builtin_cpu_init();
  const bool has[4] = {true, bool(__builtin_cpu_supports("sse4.2")),
                       __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"),
                       __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
                           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw")};
  Isa best = Isa::Scalar;
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    EXPECT_EQ(isa_supported(isa), has[int(isa)]) << to_string(isa);
    if (has[int(isa)]) best = isa;
  }
  if (!std::getenv("MINKSUM_ISA")) EXPECT_EQ(active_isa(), best);  // (the variable may force a lower one)
  std::printf("ISAs tested here: up to %s\n", to_string(best));
}

TEST(Kernels, SinglePairApiMatchesTheReference) {
  std::mt19937_64 rng(3);
  for (int k = 0; k < 1000; ++k) {
    Box a = tools::random_box(rng, 3, 2), b = tools::random_box(rng, 3, 2);
    Triangle t = tools::random_triangle(rng, 3);
    // One pair in 8 tie-heavy (tests/ties): boxes in exact contact, a box and a triangle in
    // exact contact, or lattice ones (parallel edges, shared normals).
    if (k % 8 == 3)
      a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1),
      t = test::ties::lattice_triangle(rng, 2, 1);
    if (k % 16 == 7) std::tie(a, b) = test::ties::touching_boxes(rng), t = test::ties::lattice_triangle(rng, 2, 1);
    if (k % 16 == 15) std::tie(a, t) = test::ties::touching_box_triangle(rng), b = test::ties::lattice_box(rng, 2, 1);
    BoxBoxPair pair;
    KernelPlane got[30], ref[30];
    box_box_planes(a, b, k % 2, pair);
    for (int p = 0; p < 30; ++p) got[p] = pair.plane(p);
    detail::box_box_reference(a, b, k % 2, kParallelThreshold<double>, ref);
    for (int p = 0; p < 30; ++p) {
      ASSERT_EQ(got[p].valid, ref[p].valid);
      EXPECT_LE((got[p].normal - ref[p].normal).norm(), 1e-14);
      EXPECT_NEAR(got[p].offset, ref[p].offset, 1e-12 * (1 + std::abs(ref[p].offset)));
      // Corner bits agree wherever n . u_k is not a tie (face axes tie on the other two).
      for (int bit = 0; bit < 3; ++bit) {
        if (std::abs(ref[p].normal.dot(a.rotation.col(bit))) > 1e-12)
          EXPECT_EQ(got[p].i >> bit & 1, ref[p].i >> bit & 1);
        if (std::abs(ref[p].normal.dot(b.rotation.col(bit))) > 1e-12)
          EXPECT_EQ(got[p].j >> bit & 1, ref[p].j >> bit & 1);
      }
    }
    KernelPlane tg[26], tr[26];
    box_triangle_planes(a, t, k % 2, tg);
    detail::box_triangle_reference(a, t, k % 2, kParallelThreshold<double>, tr);
    for (int p = 0; p < 26; ++p) {
      ASSERT_EQ(tg[p].valid, tr[p].valid);
      EXPECT_NEAR(tg[p].offset, tr[p].offset, 1e-12 * (1 + std::abs(tr[p].offset)));
      for (int bit = 0; bit < 3; ++bit)
        if (std::abs(tr[p].normal.dot(a.rotation.col(bit))) > 1e-12) EXPECT_EQ(tg[p].i >> bit & 1, tr[p].i >> bit & 1);
      // The triangle normal ties all three vertices, an edge cross ties the edge's two, and on
      // the lattice a box normal may tie two as well.
      if (p % 13 >= 3 || !tr[p].valid) continue;
      const int j = tr[p].j;
      ASSERT_TRUE(j >= 0 && j < 3) << "plane " << p;
      const double h[3] = {tr[p].normal.dot(t.a), tr[p].normal.dot(t.b), tr[p].normal.dot(t.c)};
      if (std::abs(h[j] - h[(j + 1) % 3]) > 1e-12 && std::abs(h[j] - h[(j + 2) % 3]) > 1e-12) EXPECT_EQ(tg[p].j, j);
    }
  }
}

// --- Topology tables: instantiate == a fresh computation for translated, scaled copies. ----

Box scaled_moved(const Box& b, double s, const Vector3d& t) {
  Box r = b;
  r.half_extents *= s;
  r.center = t;
  return r;
}

// Every instantiated facet has a valid freshly computed plane with the same normal and offset.
template <size_t P>
void expect_same_planes(const TopologyTable& t, const std::vector<double>& offsets, const KernelPlane (&fresh)[P]) {
  for (size_t f = 0; f < offsets.size(); ++f) {
    const Vector3d n(t.nx[f], t.ny[f], t.nz[f]);
    bool found = false;
    for (const auto& p : fresh)
      if (p.valid && (p.normal - n).norm() < 1e-12) {
        found = true;
        EXPECT_NEAR(offsets[f], p.offset, 1e-12 * (20 + std::abs(p.offset))) << "facet " << f;
      }
    EXPECT_TRUE(found) << "facet " << f;
  }
}

TEST(Topology, BoxBoxInstantiateEqualsFreshPlanes) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<double> u(-10, 10);
  for (bool diff : {false, true}) {
    for (int trial = 0; trial < 200; ++trial) {
      Box a = tools::random_box(rng, 0, 2), b = tools::random_box(rng, 0, 2);  // prototypes at the origin
      if (trial % 8 == 7) {  // tie-heavy (tests/ties): lattice boxes, parallel edges and shared face normals
        a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
        a.center = b.center = Vector3d::Zero();
      }
      auto A = std::make_unique<BoxBatch<double, 16>>(), B = std::make_unique<BoxBatch<double, 16>>();
      auto out = std::make_unique<BoxBoxPlanes<double, 16>>();
      A->count = B->count = 1;
      A->set(0, a), B->set(0, b);
      A->pad(), B->pad();
      box_box_planes(*A, *B, diff, *out);
      const TopologyTable t = topology_table(*out, 0, a, b, diff);
      for (int k = 0; k <= 12; ++k) {
        const double sa = std::ldexp(1.0, -k), sb = std::ldexp(1.0, -(12 - k));
        const Vector3d ta(u(rng), u(rng), u(rng)), tb(u(rng), u(rng), u(rng));
        std::vector<double> offsets(t.nx.size());
        instantiate(t, sa, ta, sb, tb, offsets.data());
        KernelPlane fresh[30];
        detail::box_box_reference(scaled_moved(a, sa, ta), scaled_moved(b, sb, tb), diff, kParallelThreshold<double>,
                                  fresh);
        expect_same_planes(t, offsets, fresh);
      }
    }
  }
}

TEST(Topology, BoxTriangleInstantiateEqualsFreshPlanes) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-10, 10);
  for (bool diff : {false, true}) {
    for (int trial = 0; trial < 200; ++trial) {
      Box box = tools::random_box(rng, 0, 2);  // the prototype octree cube, at the origin
      Triangle tri = tools::random_triangle(rng, 2);
      if (trial % 8 == 7) {  // tie-heavy (tests/ties): a lattice box and triangle
        box = test::ties::lattice_box(rng, 2, 1), tri = test::ties::lattice_triangle(rng, 2, 1);
        box.center = Vector3d::Zero();
      }
      auto A = std::make_unique<BoxBatch<double, 16>>();
      auto T = std::make_unique<TriangleBatch<double, 16>>();
      auto out = std::make_unique<BoxTrianglePlanes<double, 16>>();
      A->count = T->count = 1;
      A->set(0, box), T->set(0, tri);
      A->pad(), T->pad();
      box_triangle_planes(*A, *T, diff, *out);
      const TopologyTable t = topology_table(*out, 0, box, tri, diff);
      for (int k = 0; k <= 12; ++k) {  // octree cubes at depth k, anywhere; the triangle moved
        const double s = std::ldexp(1.0, -k);
        const Vector3d ta(u(rng), u(rng), u(rng)), tb(u(rng), u(rng), u(rng));
        std::vector<double> offsets(t.nx.size());
        instantiate(t, s, ta, 1.0, tb, offsets.data());
        const Triangle moved{tri.a + tb, tri.b + tb, tri.c + tb};
        KernelPlane fresh[26];
        detail::box_triangle_reference(scaled_moved(box, s, ta), moved, diff, kParallelThreshold<double>, fresh);
        expect_same_planes(t, offsets, fresh);
      }
    }
  }
}

// A sum's topology table, instantiated at other scales and offsets, equals the sum built
// afresh there: the same facets, their offsets within 1e-12.
void check_general_instantiate(const std::vector<Vector3d>& pair_a, const std::vector<Vector3d>& pair_b, bool lattice,
                               std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-10, 10);
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_points(pair_a, A), Status::Ok);
  ASSERT_EQ(polytope_from_points(pair_b, B), Status::Ok);
  for (bool diff : {false, true}) {
    MinkowskiSum m;
    ASSERT_EQ(diff ? minkowski_difference(A, B, m) : minkowski_sum(A, B, m), Status::Ok);
    const TopologyTable t = topology_table(m, A, B, diff);
    ASSERT_EQ(int(t.nx.size()), m.F);
    for (int k = 0; k <= 12; ++k) {
      const double sa = std::ldexp(1.0, -k), sb = 1.5;
      // (Offsets on a grid of 2^-10, so that the moved points are exact: rounded, a face's
      // corners would leave its plane, and the exact hull would split it.)
      Vector3d ta(u(rng), u(rng), u(rng)), tb(u(rng), u(rng), u(rng));
      ta = (1024 * ta).array().round() / 1024, tb = (1024 * tb).array().round() / 1024;
      if (lattice) ta = test::ties::lattice_point(rng, 10, 4), tb = test::ties::lattice_point(rng, 10, 4);
      std::vector<Vector3d> pa, pb;
      for (const auto& p : pair_a) pa.push_back(sa * p + ta);
      for (const auto& p : pair_b) pb.push_back(sb * p + tb);
      ConvexPolytope A2, B2;
      ASSERT_EQ(polytope_from_points(pa, A2), Status::Ok);
      ASSERT_EQ(polytope_from_points(pb, B2), Status::Ok);
      MinkowskiSum fresh;
      ASSERT_EQ(diff ? minkowski_difference(A2, B2, fresh) : minkowski_sum(A2, B2, fresh), Status::Ok);
      std::vector<double> offsets(m.F);
      instantiate(t, sa, ta, sb, tb, offsets.data());
      ASSERT_EQ(fresh.F, m.F);
      for (int f = 0; f < m.F; ++f) {
        const Vector3d n(t.nx[f], t.ny[f], t.nz[f]);
        double best = 1e300;
        for (const auto& p : fresh.planes)
          if ((p.normal - n).norm() < 1e-9) best = std::min(best, std::abs(p.offset - offsets[f]));
        EXPECT_LT(best, 1e-12 * 30) << "facet " << f << " scale 2^-" << k;
      }
    }
  }
}

TEST(Topology, GeneralInstantiateEqualsFreshSum) {
  std::mt19937_64 rng(19);
  // The icosahedron and dodecahedron, then tie-heavy pairs (tests/ties: lattice points, with
  // coplanar faces, parallel edges and shared normals) under lattice offsets, which keep them exact.
  const auto table1 = tools::table1_pairs()[5];
  for (int pair = 0; pair < 4; ++pair) {
    const bool lattice = pair > 0;
    const std::vector<Vector3d> pair_a = lattice ? test::ties::lattice_solid_points(rng, 2, 1) : table1.a;
    const std::vector<Vector3d> pair_b = lattice ? test::ties::lattice_solid_points(rng, 2, 1) : table1.b;
    check_general_instantiate(pair_a, pair_b, lattice, rng);
  }
}

}  // namespace
}  // namespace minksum
