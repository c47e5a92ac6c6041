// Rounded ties: shapes whose coordinates are rounded (cos/sin prisms, boxes turned by a rounded
// angle, CAD-like decimals), whose faces' exact normals are not doubles, in the poses that keep
// their ties (aligned, turned about a shared axis, scaled by a power of two). The structure of
// every sum must be CGAL's exact hull of the exact pairwise sums (Epeck), facet by facet:
// exactly parallel faces merge and true slivers stay.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <set>
#include <string>

#include "support/cgal_peer.hpp"
#include "checks.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

using tools::cos_sin_prism;
using tools::turned_box;

// Every coordinate printed with `digits` significant digits and read back (a CAD file's).
std::vector<Vector3d> decimal(std::vector<Vector3d> p, int digits) {
  char text[64];
  for (auto& v : p)
    for (int k = 0; k < 3; ++k) {
      std::snprintf(text, sizeof text, "%.*g", digits, v[k]);
      v[k] = std::strtod(text, nullptr);
    }
  return p;
}

// A (+) sB through the polytopes equals CGAL's exact hull of the pairwise sums (vertices matched
// within tol times the largest coordinate).
testing::AssertionResult exact_structure(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                         double tol = 1e-12) {
  ConvexPolytope A, B;
  if (polytope_from_points(a, A) != Status::Ok || polytope_from_points(b, B) != Status::Ok)
    return testing::AssertionFailure() << "an operand was not built";
  MinkowskiSum m;
  if ((s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m)) != Status::Ok)
    return testing::AssertionFailure() << "the sum failed";
  if (m.corrected) return testing::AssertionFailure() << "the corrector ran";
  return test::equals_exact_hull(a, b, s, m, tol);
}

TEST(RoundedTies, AlignedPrismsOfHalfRadius) {
  for (int n : {6, 8, 12, 16, 24, 32})
    for (double s : {1.0, -1.0})
      EXPECT_TRUE(exact_structure(cos_sin_prism(n, 1, -1, 1), cos_sin_prism(n, 0.5, -0.5, 0.5), s)) << n << " sides, sign " << s;
}

TEST(RoundedTies, AlignedPrismsOfOtherRadius) {
  for (int n : {6, 8, 12, 16, 24, 32})
    for (double s : {1.0, -1.0})
      EXPECT_TRUE(exact_structure(cos_sin_prism(n, 1, -1, 1), cos_sin_prism(n, 0.37, -0.3, 0.2), s)) << n << " sides, sign " << s;
}

TEST(RoundedTies, DecimalPrisms) {
  for (int n : {6, 8, 16, 32})
    for (int digits : {15, 16, 17})
      EXPECT_TRUE(exact_structure(decimal(cos_sin_prism(n, 1, -1, 1), digits), decimal(cos_sin_prism(n, 0.5, -0.5, 0.5), digits), 1))
          << n << " sides, " << digits << " digits";
}

TEST(RoundedTies, BoxTurnedOnBox) {
  for (double angle : {0.1, 0.5, 1.0, M_PI / 6, M_PI / 7})
    EXPECT_TRUE(exact_structure(turned_box({1, 0.7, 0.3}, 0), turned_box({0.31, 0.23, 0.5}, angle), 1)) << angle;
}

// Table 1's B turned back into A's frame: a rounded copy of A's shape whose faces lie within
// rounding of A's, so that every sign of the overlay is a near-tie (det ~ 1e-17), and the sum
// has slivers an ulp wide (vertices matched exactly: CGAL's doubles of the exact vertices are
// ours here). The pairs with planar faces only: a turned cube's or dodecahedron's faces are
// planar to a tolerance (README).
TEST(RoundedTies, Table1PairsTurnedBackIntoOneFrame) {
  const Eigen::Matrix3d R = tools::table1_rotation();
  for (const auto& pair : tools::table1_pairs()) {
    if (pair.name != "cube_icosa" && pair.name != "icosa_icosa") continue;
    const auto back = tools::rotated(tools::rotated(pair.b_body, R), R.transpose());
    for (double s : {1.0, -1.0}) EXPECT_TRUE(exact_structure(pair.a, back, s, 0)) << pair.name << ", sign " << s;
  }
}

TEST(RoundedTies, PrismOnBox) {
  for (int n : {5, 8, 13, 16})
    EXPECT_TRUE(exact_structure(turned_box({1, 0.7, 0.3}, 0), cos_sin_prism(n, 0.41, -0.2, 0.3, 0.1), 1)) << n;
}

// A random pair that keeps a rounded tie: cos/sin prisms of 3 to 128 sides (aligned with the
// same polygon, one halved or doubled, one of another radius, or turned about the shared axis
// by any angle), a prism on a box, boxes turned about z by any angle, a generic polytope of
// rounded points with a copy of itself (times 1, 1/2 or 2), each possibly printed to 15-17
// digits and read back (a CAD file's coordinates).
struct RoundedCase {
  std::vector<Vector3d> a, b;
  double sign;
  std::string what;
};

RoundedCase rounded_case(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> size(0.2, 1.5), turn(0, 2 * M_PI);
  // Mostly 3 to 16 sides; one in 16 up to 128, then against a box or a small prism (the exact
  // oracle's cost grows with the product of the vertex counts).
  const bool large = rng() % 16 == 0;
  const int n = large ? 17 + int(rng() % 112) : 3 + int(rng() % 14);
  const int m = large ? 3 + int(rng() % 6) : 3 + int(rng() % 14);
  const double r = size(rng), h0 = -size(rng), h1 = size(rng), g0 = -size(rng) / 2, g1 = size(rng) / 2;
  const double phase = rng() % 2 ? 0.0 : turn(rng);
  RoundedCase c;
  c.sign = rng() % 2 ? 1.0 : -1.0;
  const int kind = int(rng() % 8);
  c.a = cos_sin_prism(n, r, h0, h1, phase);
  switch (kind) {
    case 0:  // the same polygon, another slab
      c.b = cos_sin_prism(n, r, g0, g1, phase), c.what = "same polygon";
      break;
    case 1:  // halved or doubled
      c.b = cos_sin_prism(n, rng() % 2 ? r / 2 : 2 * r, g0, g1, phase), c.what = "scaled by 2";
      break;
    case 2:  // another radius (no exact parallels: true slivers)
      c.b = cos_sin_prism(large ? m : n, size(rng), g0, g1, phase), c.what = "other radius";
      break;
    case 3:  // turned about the shared axis
      c.b = cos_sin_prism(m, size(rng), g0, g1, turn(rng)), c.what = "turned about the axis";
      break;
    case 4:  // on a box turned about the axis
      c.b = turned_box(Vector3d(size(rng), size(rng), size(rng)) / 2, rng() % 2 ? 0.0 : turn(rng)), c.what = "box";
      break;
    case 5:  // two boxes turned about z
      c.a = turned_box(Vector3d(size(rng), size(rng), size(rng)), phase);
      c.b = turned_box(Vector3d(size(rng), size(rng), size(rng)) / 2, turn(rng)), c.what = "boxes";
      break;
    case 6: {  // a generic polytope of rounded points with itself, halved or doubled: every face
      // has a parallel twin (or an opposite one in the difference), and no axis in sight
      c.a = tools::sphere_points(4 + int(rng() % 13), unsigned(rng()));
      const double k = rng() % 3 == 0 ? 1.0 : rng() % 2 ? 0.5 : 2.0;
      c.b = c.a;
      for (auto& p : c.b) p *= k;
      c.what = "a polytope and its copy times " + std::to_string(k);
      break;
    }
    default: {  // a polytope and a copy at another size, each turned by one rotation and rounded
      // apart: every face within rounding of parallel to its twin (near-ties, det ~ 1e-17)
      const auto points = tools::sphere_points(4 + int(rng() % 13), unsigned(rng()));
      const Eigen::Matrix3d R = tools::axis_angle(Vector3d(size(rng), -size(rng), size(rng)), turn(rng));
      const double k = size(rng);
      c.a = tools::rotated(points, R), c.b = points;
      for (auto& p : c.b) p = R * (k * p);
      c.what = "a polytope and its copy times " + std::to_string(k) + ", both turned";
    }
  }
  if (rng() % 4 == 0) {
    const int digits = 15 + int(rng() % 3);
    c.a = decimal(c.a, digits), c.b = decimal(c.b, digits), c.what += ", " + std::to_string(digits) + " digits";
  }
  c.what += ", " + std::to_string(c.a.size() / 2) + " and " + std::to_string(c.b.size() / 2) + " sides";
  return c;
}

// A uniformly random rotation, rounded (a user's).
Eigen::Matrix3d random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> g;
  return Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
}

// Whether m and n have the same structure: the same facets by their vertices' pairs (i, j).
testing::AssertionResult same_structure(const MinkowskiSum& m, const MinkowskiSum& n) {
  if (m.V != n.V || m.E != n.E || m.F != n.F)
    return testing::AssertionFailure() << "V, E, F " << m.V << "/" << m.E << "/" << m.F << " and " << n.V << "/"
                                       << n.E << "/" << n.F;
  const auto facets = [](const MinkowskiSum& x) {
    std::multiset<std::vector<std::pair<int, int>>> out;
    for (int f = 0; f < x.F; ++f) {
      std::vector<std::pair<int, int>> pairs;
      for (int v : x.facet(f)) pairs.push_back({x.vertices[v].i, x.vertices[v].j});
      std::sort(pairs.begin(), pairs.end());
      out.insert(pairs);
    }
    return out;
  };
  if (facets(m) != facets(n)) return testing::AssertionFailure() << "a facet has other vertex pairs";
  return testing::AssertionSuccess();
}

// A sum keeps its memos of rounded ties and of exact normals from one call to the next while
// the shapes (and, for the ties, their relative rotation) stay (Overlay::run). One call after
// another in one thread, B rebuilt in the same variable (where the last shape was freed) from
// exact parallels to slivers and back, summed and differenced, turned against A in between and
// placed under a common rotation: each sum at identity poses must still be the exact hull, and
// each under the common rotation have its structure. Two families: aligned cos/sin prisms, and
// a polytope of rounded points (exact normals computed when needed, GaussKind::OnDemand) with
// copies of itself. The slivers are the parallel copy's points moved off their lines by a
// rounded factor, so that their faces keep the indices the memos hold.
TEST(RoundedTies, RememberedTiesFollowTheShapes) {
  const auto times = [](std::vector<Vector3d> p, double kx, double kz) {
    for (auto& v : p) v = Vector3d(kx * v.x(), kx * v.y(), kz * v.z());
    return p;
  };
  const std::vector<Vector3d> prism = cos_sin_prism(16, 0.5, -0.5, 0.5), points = tools::sphere_points(14, 5);
  const struct {
    std::vector<Vector3d> a, parallel, sliver;
  } families[] = {{cos_sin_prism(16, 1, -1, 1), prism, times(prism, 0.74, 1)},
                  {points, times(points, 0.5, 0.5), times(points, 0.37, 0.37)}};
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d common = identity, turned = identity;
  common.linear() = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  turned.linear() = Eigen::AngleAxisd(0.2, Vector3d(3, -1, 2).normalized()).toRotationMatrix();
  for (const auto& family : families) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(family.a, A), Status::Ok);
    for (double s : {1.0, -1.0})
      for (const auto* b : {&family.parallel, &family.sliver, &family.parallel, &family.sliver}) {
        ASSERT_EQ(shape_from_points(*b, B), Status::Ok);
        const auto sum = [&](const Eigen::Isometry3d& pa, const Eigen::Isometry3d& pb, MinkowskiSum& out) {
          return s > 0 ? minkowski_sum(A, pa, B, pb, out) : minkowski_difference(A, pa, B, pb, out);
        };
        MinkowskiSum first, other, again, under_common;
        ASSERT_EQ(sum(identity, identity, first), Status::Ok);
        ASSERT_EQ(sum(identity, turned, other), Status::Ok);
        ASSERT_EQ(sum(identity, identity, again), Status::Ok);
        ASSERT_EQ(sum(common, common, under_common), Status::Ok);
        const std::string what = std::string(b == &family.parallel ? "parallel" : "slivers") + ", sign " +
                                 std::to_string(int(s)) + ", " + std::to_string(family.a.size()) + " points";
        EXPECT_TRUE(test::equals_exact_hull(family.a, *b, s, first, 1e-12)) << what;
        EXPECT_TRUE(test::equals_exact_hull(family.a, *b, s, again, 1e-12)) << what << ", after B turned";
        EXPECT_TRUE(same_structure(first, under_common)) << what << ", under a common rotation";
      }
  }
}

// 10 shards of 1,000 random rounded pairs (sums and differences) against CGAL's exact hull;
// one pair in eight also as prepared shapes under one random rounded rotation and translation
// each (the structure depends only on the relative rotation, exactly the identity here): the
// same structure as the unposed sum.
class RoundedPairs : public testing::TestWithParam<int> {};

// Under a sanitizer (memory safety; a twentieth of the pairs already) the oracle, many times slower
// there than the sums, checks every tenth pair; the others' sums still run and must be Ok.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
constexpr int kOracleEvery = 10;
#else
constexpr int kOracleEvery = 1;
#endif

TEST_P(RoundedPairs, EqualTheExactHull) {
  std::mt19937_64 rng(7000 + unsigned(GetParam()));
  std::uniform_real_distribution<double> shift(-3, 3);
  const int pairs = test::scaled(1000);
  for (int k = 0; k < pairs; ++k) {
    const RoundedCase c = rounded_case(rng);
    if (k % kOracleEvery == 0) {
      ASSERT_TRUE(exact_structure(c.a, c.b, c.sign)) << "pair " << k << ": " << c.what << ", sign " << c.sign;
    } else {
      ConvexPolytope A, B;
      MinkowskiSum m;
      ASSERT_EQ(polytope_from_points(c.a, A), Status::Ok);
      ASSERT_EQ(polytope_from_points(c.b, B), Status::Ok);
      ASSERT_EQ(c.sign > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m), Status::Ok);
      ASSERT_FALSE(m.corrected) << "pair " << k << ": " << c.what;
    }
    if (k % 8 != 0) continue;
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(c.a, A), Status::Ok);
    ASSERT_EQ(shape_from_points(c.b, B), Status::Ok);
    Eigen::Isometry3d pa = Eigen::Isometry3d::Identity(), pb;
    pa.linear() = random_rotation(rng), pa.translation() = Vector3d(shift(rng), shift(rng), shift(rng));
    pb = pa, pb.translation() = Vector3d(shift(rng), shift(rng), shift(rng));
    const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
    MinkowskiSum plain, posed;
    const auto sum = [&](const Eigen::Isometry3d& x, const Eigen::Isometry3d& y, MinkowskiSum& out) {
      return c.sign > 0 ? minkowski_sum(A, x, B, y, out) : minkowski_difference(A, x, B, y, out);
    };
    ASSERT_EQ(sum(identity, identity, plain), Status::Ok);
    ASSERT_EQ(sum(pa, pb, posed), Status::Ok);
    ASSERT_FALSE(posed.corrected);
    ASSERT_TRUE(same_structure(plain, posed)) << "pair " << k << ": " << c.what;
    if (k % 24 != 0) continue;
    // Every 24th pair a level short of the whole, against the exact hull too: the planes level
    // and the vertices level in turn.
    const SumParts parts = k % 48 == 0 ? SumParts::Planes : SumParts::Vertices;
    MinkowskiSum level;
    ASSERT_EQ(c.sign > 0 ? minkowski_sum(A, identity, B, identity, level, parts)
                         : minkowski_difference(A, identity, B, identity, level, parts),
              Status::Ok);
    const std::vector<Vector3d>&a = A.polytope().vertices, &b = B.polytope().vertices;
    EXPECT_TRUE(parts == SumParts::Planes ? test::equals_exact_planes(a, b, c.sign, level, 1e-12)
                                          : test::equals_exact_vertices(a, b, c.sign, level, 1e-12))
        << "pair " << k << ": " << c.what;
  }
}

INSTANTIATE_TEST_SUITE_P(Shards, RoundedPairs, testing::Range(0, 10));

}  // namespace
}  // namespace minksum
