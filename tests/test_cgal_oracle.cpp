// The exact oracle: CGAL's exact kernel (Epeck) builds the hull of the pairwise sums and merges
// exactly coplanar triangles (peers::exact_counts, in tests/support/cgal_peer.cpp); its V, E, F must
// equal the fast path's. CGAL's exact polytope distance checks the queries.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "support/cgal_peer.hpp"
#include "checks.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

using tools::exact_rotated;
using tools::scaled;

// m is the exact A (+) sB of the point sets (whose pairwise sums are doubles): CGAL's exact hull
// of the pairwise sums with coplanar triangles merged has the same V, E, F, and every facet the
// same vertices exactly; and the fast path did not need the corrector.
testing::AssertionResult equals_exact(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, double s,
                                      const MinkowskiSum& m) {
  if (m.corrected) return testing::AssertionFailure() << "the corrector ran";
  return test::equals_exact_hull(a, b, s, m, 0);
}

void expect_matches_oracle(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, int expected_F = -1) {
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_points(a, A), Status::Ok);
  ASSERT_EQ(polytope_from_points(b, B), Status::Ok);
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    ASSERT_EQ(s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m), Status::Ok);
    EXPECT_FALSE(m.corrected) << "sign " << s;
    // Facet by facet, the same vertices (exactly where the pairwise sums are doubles).
    EXPECT_TRUE(test::equals_exact_hull(a, b, s, m, 1e-12)) << "sign " << s;
    if (expected_F >= 0) EXPECT_EQ(m.F, expected_F) << "sign " << s;
  }
}

TEST(ExactOracle, Table1PairsWithExactCoordinates) {
  for (const auto& pair : tools::table1_pairs()) {
    SCOPED_TRACE(pair.name);
    expect_matches_oracle(pair.a, pair.b, pair.name == "cube_rotcube" ? 30 : -1);
  }
}

std::vector<Vector3d> box(const Vector3d& h, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  std::vector<Vector3d> p;
  for (const auto& q : tools::cube_points()) p.push_back(R * q.cwiseProduct(h));
  return p;
}

TEST(ExactOracle, AlignedBoxes) { expect_matches_oracle(box({1, 2, 3}), box({0.5, 0.25, 4}), 6); }

TEST(ExactOracle, FortyFiveDegreesAboutZ) {
  expect_matches_oracle(box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4)), 10);
}

TEST(ExactOracle, TriangleCoplanarWithABoxFace) {
  expect_matches_oracle(box({1, 1, 1}), {{-0.5, -0.5, 1}, {0.75, -0.25, 1}, {0.125, 0.5, 1}}, 9);
}

TEST(ExactOracle, TrianglePlusTriangle) {
  expect_matches_oracle({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
                        {{0.25, 0.125, -0.5}, {0.375, 0.25, 0.75}, {-0.5, 0.75, 0.125}});
}

TEST(ExactOracle, IdenticalAndMirroredPolytopes) {
  const auto d = exact_rotated(scaled(tools::exact_dodecahedron_points(), 30));
  expect_matches_oracle(d, d, 12);
  std::vector<Vector3d> mirrored;
  for (const auto& p : d) mirrored.push_back(Vector3d(-p.x(), p.y(), p.z()));
  expect_matches_oracle(d, mirrored);
}

TEST(ExactOracle, ThinBox) {
  expect_matches_oracle(box({1, 1, 1e-7}), exact_rotated(scaled(tools::cube_points(), 30)));
}

// --- Exact ties: integer grids and degenerate families (issue 29) --------------------------

// Both sums (A (+) B, A (-) B) of the point sets, through the polytopes and through prepared
// shapes, against the exact structure.
void expect_exact_both_ways(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_points(a, A), Status::Ok);
  ASSERT_EQ(polytope_from_points(b, B), Status::Ok);
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m, posed;
    ASSERT_EQ(s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m), Status::Ok);
    EXPECT_TRUE(equals_exact(a, b, s, m)) << "sign " << s;
    ASSERT_EQ(s > 0 ? minkowski_sum(SA, I, SB, I, posed) : minkowski_difference(SA, I, SB, I, posed), Status::Ok);
    EXPECT_TRUE(equals_exact(a, b, s, posed)) << "shapes, sign " << s;
  }
}

// The inputs of issue 29: ties that overflowed the loop buffer (a merged facet longer than the
// face it was counted as) and ties that split a facet (a face normal rounded off an arc's
// circle).
TEST(ExactTies, TheLoopBufferOverflow) {
  const std::vector<Vector3d> a = {{2, 11, 0}, {-2, 14, 0}, {3, 4, 5}, {6, 8, 5}};
  const auto cube = scaled(tools::cube_points(), 0.5);
  expect_exact_both_ways(a, cube);
  expect_exact_both_ways(cube, a);
}

TEST(ExactTies, TheSplitFacet) {
  const std::vector<Vector3d> a = {{-1, 2, -2}, {0, 2, -2},  {-2, -1, 2}, {1, -1, 0},
                                   {0, 2, 0},   {1, -2, -2}, {1, 1, 1},   {1, 0, -2}};
  const std::vector<Vector3d> b = {{-2, 0, 0}, {1, -1, 2}, {-2, -1, 2}, {0, -1, 2}, {-2, 2, 0}};
  expect_exact_both_ways(a, b);
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_points(a, A), Status::Ok);
  ASSERT_EQ(polytope_from_points(b, B), Status::Ok);
  MinkowskiSum m;
  ASSERT_EQ(minkowski_sum(A, B, m), Status::Ok);
  EXPECT_EQ(m.V, 18);  // and the oracle's too (above)
  EXPECT_EQ(m.E, 36);
  EXPECT_EQ(m.F, 20);
}

// FCL's signed-distance "regression 7" (a robotics user's box pair): a box turned about z by a
// quarter turn less 0.000796 rad, and one turned by a product of quarter turns whose matrix has
// 6e-17 where zeros belong, both centred at (0.75, 0, 0.15). Their world corners are what a
// user sums; the sums are not doubles, so the exact counts come from CGAL's exact kernel.
TEST(ExactTies, FclBoxRegression7) {
  Box b1, b2;
  b1.half_extents = Vector3d(0.050000000000000002776, 0.55000000000000004441, 0.2999999999999999889) / 2;
  b1.rotation << 0.00079632671073326442932, -0.99999968293183538748, 0, 0.99999968293183538748,
      0.00079632671073326442932, 0, 0, 0, 1;
  b1.center = Vector3d(0.75000000000000055511, -2.4083553715553102684e-15, 0.14999999999999999445);
  b2.half_extents = Vector3d(0.25, 0.2000000000000000111, 0.14999999999999999445) / 2;
  b2.rotation << 6.1232339957367660359e-17, 0, 1, -1, 6.1232339957367660359e-17, 6.1232339957367660359e-17,
      -6.1232339957367660359e-17, -1, 3.7493994566546440196e-33;
  b2.center = Vector3d(0.75, 0, 0.14999999999999999445);
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_box(b1, A), Status::Ok);
  ASSERT_EQ(polytope_from_box(b2, B), Status::Ok);
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    ASSERT_EQ(s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m), Status::Ok);
    EXPECT_FALSE(m.corrected);
    EXPECT_TRUE(test::valid_sum(A.vertices, B.vertices, s, A, B, m, 1e-12, 1e-12, 500));
    const peers::ExactCounts e = peers::exact_counts(A.vertices, B.vertices, s);
    EXPECT_EQ(m.V, e.V) << "sign " << s;
    EXPECT_EQ(m.E, e.E) << "sign " << s;
    EXPECT_EQ(m.F, e.F) << "sign " << s;
  }
  MinkowskiSum boxes;  // the box-box entry (its general path: the boxes are not in general position)
  ASSERT_EQ(minkowski_sum(b1, b2, boxes), Status::Ok);
  EXPECT_EQ(boxes.F, peers::exact_counts(A.vertices, B.vertices, 1).F);
}

// Integer points in [-r, r]^3, r = 1 ... 8, 4 to 40 of them: ties everywhere (parallel faces and
// edges, coplanar points, faces on faces). 20 shards of 5,000 pairs, each as a sum and a
// difference, through the polytopes; one pair in ten also through prepared shapes under
// signed-permutation poses and integer translations (which keep every tie exact).
class IntegerGrids : public testing::TestWithParam<int> {};

Eigen::Isometry3d signed_permutation_pose(std::mt19937_64& rng) {
  static const int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
  const int p = int(rng() % 6);
  double sign[3] = {rng() % 2 ? 1.0 : -1.0, rng() % 2 ? 1.0 : -1.0, 0};
  sign[2] = (p < 3 ? 1 : -1) * sign[0] * sign[1];  // a rotation: determinant +1
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear().setZero();
  for (int k = 0; k < 3; ++k) pose.linear()(k, kPerm[p][k]) = sign[k];
  std::uniform_int_distribution<int> t(-20, 20);
  pose.translation() = Vector3d(t(rng), t(rng), t(rng));
  return pose;
}

std::vector<Vector3d> moved(const std::vector<Vector3d>& pts, const Eigen::Isometry3d& pose) {
  std::vector<Vector3d> out;
  for (const auto& p : pts) out.push_back(pose * p);
  return out;
}

// The posed sums of prepared shapes under exact poses against the exact structure of the moved
// points; with `planes`, the planes and vertices levels too (SumParts::Planes, Vertices), within
// tol of the size.
void expect_posed_exact(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, const Eigen::Isometry3d& pa,
                        const Eigen::Isometry3d& pb, double s, bool planes = false, double tol = 0) {
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  MinkowskiSum m;
  ASSERT_EQ(s > 0 ? minkowski_sum(SA, pa, SB, pb, m) : minkowski_difference(SA, pa, SB, pb, m), Status::Ok);
  // The shapes' vertices are their input points in input order less duplicates and interior ones.
  const std::vector<Vector3d> va = moved(SA.polytope().vertices, pa), vb = moved(SB.polytope().vertices, pb);
  if (tol == 0) EXPECT_TRUE(equals_exact(va, vb, s, m));
  if (tol > 0) EXPECT_TRUE(test::equals_exact_hull(va, vb, s, m, tol));
  if (!planes) return;
  const SumParts P = SumParts::Planes;
  ASSERT_EQ(s > 0 ? minkowski_sum(SA, pa, SB, pb, m, P) : minkowski_difference(SA, pa, SB, pb, m, P), Status::Ok);
  EXPECT_TRUE(test::equals_exact_planes(va, vb, s, m, std::max(tol, 1e-12))) << "planes level";
  const SumParts V = SumParts::Vertices;
  ASSERT_EQ(s > 0 ? minkowski_sum(SA, pa, SB, pb, m, V) : minkowski_difference(SA, pa, SB, pb, m, V), Status::Ok);
  EXPECT_TRUE(test::equals_exact_vertices(va, vb, s, m, std::max(tol, 1e-12))) << "vertices level";
}

TEST_P(IntegerGrids, SumsAndDifferencesAreTheExactHull) {
  std::mt19937_64 rng(29000 + unsigned(GetParam()));
  std::uniform_int_distribution<int> radius(1, 8), count(4, 40);
  int checked = 0;
  for (int k = 0; k < test::scaled(5000); ++k) {
    SCOPED_TRACE("shard " + std::to_string(GetParam()) + " pair " + std::to_string(k));
    std::vector<Vector3d> pts[2];
    for (auto& p : pts) {
      const int r = radius(rng), n = count(rng);
      std::uniform_int_distribution<int> c(-r, r);
      for (int i = 0; i < n; ++i) p.emplace_back(c(rng), c(rng), c(rng));
    }
    ConvexPolytope A, B;
    if (polytope_from_points(pts[0], A) != Status::Ok || polytope_from_points(pts[1], B) != Status::Ok) continue;
    const bool coplanar_flats = A.flat && B.flat && A.faces[0].normal.cross(B.faces[0].normal).norm() <= 1e-12;
    for (double s : {1.0, -1.0}) {
      MinkowskiSum m;
      const Status st = s > 0 ? minkowski_sum(A, B, m) : minkowski_difference(A, B, m);
      if (coplanar_flats) {
        ASSERT_EQ(st, Status::DegenerateResult);
        continue;
      }
      ASSERT_EQ(st, Status::Ok);
      ASSERT_TRUE(equals_exact(pts[0], pts[1], s, m)) << "sign " << s;
      ++checked;
    }
    if (k % 10 == 0 && !coplanar_flats)
      expect_posed_exact(pts[0], pts[1], signed_permutation_pose(rng), signed_permutation_pose(rng),
                         k % 20 == 0 ? 1 : -1, k % 30 == 0);
  }
  EXPECT_GT(checked, test::scaled(5000));
}

INSTANTIATE_TEST_SUITE_P(Shards, IntegerGrids, testing::Range(0, 20));

// The degenerate families (tools::degenerate_pair: aligned boxes, boxes about a shared axis,
// aligned prisms of 8 to 64 sides, a box with a prism, two copies, A (-) A, coplanar faces), 300
// seeded members each, sum and difference: through the polytopes, and through prepared shapes
// at poses that keep the family's ties (the same signed permutation for both; for the copies and
// the mirrored pair any common rotation, whose rounding is the same for both).
class DegenerateFamilies : public testing::TestWithParam<int> {};

TEST_P(DegenerateFamilies, HaveTheExactStructure) {
  const int family = GetParam();
  std::mt19937_64 rng(2900 + unsigned(family));
  for (int k = 0; k < test::scaled(300); ++k) {
    const tools::DegeneratePair pair = tools::degenerate_pair(family, rng);
    SCOPED_TRACE(pair.name + " " + std::to_string(k));
    expect_exact_both_ways(pair.a, pair.b);
    Eigen::Isometry3d pose = signed_permutation_pose(rng), pb = pose;
    pb.translation() = signed_permutation_pose(rng).translation();
    expect_posed_exact(pair.a, pair.b, pose, pb, pair.difference || k % 2 ? -1 : 1, k % 10 == 0);
    if (pair.name == "identical" || pair.name == "mirrored") {
      // A common generic rotation: the structure of the body-frame pair.
      std::uniform_real_distribution<double> u(-1, 1);
      Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();
      turn.linear() = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
      ConvexShape SA, SB;
      ASSERT_EQ(shape_from_points(pair.a, SA), Status::Ok);
      ASSERT_EQ(shape_from_points(pair.b, SB), Status::Ok);
      MinkowskiSum m;
      const double s = pair.difference ? -1 : 1;
      ASSERT_EQ(s > 0 ? minkowski_sum(SA, turn, SB, turn, m) : minkowski_difference(SA, turn, SB, turn, m), Status::Ok);
      std::vector<std::vector<Vector3d>> unused;
      const peers::ExactCounts e = peers::exact_structure(pair.a, pair.b, s, &unused);
      EXPECT_FALSE(m.corrected);
      EXPECT_EQ(m.V, e.V);
      EXPECT_EQ(m.E, e.E);
      EXPECT_EQ(m.F, e.F);
    }
  }
}

// The planes and vertices levels (SumParts::Planes, Vertices) of generic posed pairs: random
// polytopes of 4 to 64 points, flat ones (a triangle, which takes the whole path) among them,
// at random poses, against the exact hull of the moved points.
TEST(SumParts, PlanesAndVerticesOfPosedPairsAreTheExactHulls) {
  std::mt19937_64 rng(5501);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> count(4, 64);
  const auto pose = [&] {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
    p.translation() = 5 * Vector3d(u(rng), u(rng), u(rng));
    return p;
  };
  for (int k = 0; k < test::scaled(200, 20); ++k) {
    SCOPED_TRACE("pair " + std::to_string(k));
    std::vector<Vector3d> pts[2];
    for (auto& p : pts) {
      if (k % 5 == 0 && &p == &pts[1]) {
        for (int i = 0; i < 3; ++i) p.emplace_back(u(rng), u(rng), u(rng));  // a triangle
        continue;
      }
      p = tools::sphere_points(count(rng), unsigned(rng()));
      for (auto& x : p) x = x.cwiseProduct(Vector3d(1 + u(rng), 1 + u(rng), 1 + u(rng)).cwiseAbs());
    }
    expect_posed_exact(pts[0], pts[1], pose(), pose(), k % 2 ? -1 : 1, true, 1e-9);
  }
}

INSTANTIATE_TEST_SUITE_P(Families, DegenerateFamilies, testing::Range(0, tools::kDegenerateFamilies),
                         [](const testing::TestParamInfo<int>& info) {
                           std::mt19937_64 rng(1);
                           return tools::degenerate_pair(info.param, rng).name;
                         });

// A tie-heavy pair (tests/ties) of the given kind: boxes, a box and a triangle, or two
// triangles in exact contact; or two lattice solids.
void tie_pair(std::mt19937_64& rng, int kind, std::vector<Vector3d> (&pts)[2]) {
  if (kind == 0) {
    const auto [a, b] = test::ties::touching_boxes(rng);
    pts[0] = test::ties::corners(a), pts[1] = test::ties::corners(b);
  } else if (kind == 1) {
    const auto [a, b] = test::ties::touching_box_triangle(rng);
    pts[0] = test::ties::corners(a), pts[1] = test::ties::corners(b);
  } else if (kind == 2) {
    const auto [a, b] = test::ties::touching_triangles(rng);
    pts[0] = test::ties::corners(a), pts[1] = test::ties::corners(b);
  } else {
    pts[0] = test::ties::lattice_solid_points(rng, 2, 1), pts[1] = test::ties::lattice_solid_points(rng, 2, 1);
  }
}

TEST(ExactOracle, DistancesAgreeWithCgalPolytopeDistance) {
  std::mt19937_64 rng(81);
  std::uniform_int_distribution<int> count(4, 20);
  std::uniform_real_distribution<double> u(-1, 1);
  int separated = 0, touching = 0;
  for (int k = 0; k < 3000; ++k) {
    std::vector<Vector3d> pts[2];
    for (auto& pt : pts) {
      const Vector3d c = 2 * Vector3d(u(rng), u(rng), u(rng));
      if (k % 3 == 0) {  // boxes
        const Box b = tools::random_box(rng, 0);
        for (const auto& q : tools::cube_points()) pt.push_back(c + b.rotation * q.cwiseProduct(b.half_extents));
      } else if (k % 3 == 1) {  // triangles
        for (int v = 0; v < 3; ++v) pt.push_back(c + Vector3d(u(rng), u(rng), u(rng)));
      } else {  // random polytopes
        for (const auto& q : tools::sphere_points(count(rng), unsigned(rng()))) pt.push_back(c + q);
      }
    }
    const bool ties = k % 8 == 7;  // tie-heavy (tests/ties): in exact contact, or lattice shapes
    if (ties) tie_pair(rng, k / 8 % 4, pts);
    ConvexPolytope A, B;
    ASSERT_EQ(polytope_from_points(pts[0], A), Status::Ok);
    ASSERT_EQ(polytope_from_points(pts[1], B), Status::Ok);
    Proximity p;
    ASSERT_EQ(proximity(A, B, p), Status::Ok);
    const double exact = peers::cgal_distance(pts[0], pts[1]);
    EXPECT_NEAR(p.distance, exact, 1e-9 * (1 + exact)) << "pair " << k;
    if (ties) {  // the verdict exactly; exactly 0 at contact
      EXPECT_EQ(p.intersecting, exact == 0) << "pair " << k << ": exact distance " << exact;
      if (exact == 0) EXPECT_EQ(p.distance, 0.0) << "pair " << k;
      touching += exact == 0;
    }
    separated += exact > 0;
  }
  EXPECT_GT(touching, 3000 / 8 / 2);
  EXPECT_GT(separated, 1000);  // and the rest overlap: both outcomes are exercised
  EXPECT_LT(separated, 2900);
}

// Boxes whose nearest features are nearly parallel edges (turned by 1e-2 ... 1e-9 rad against
// each other, 1e-5 ... 0.1 of their size apart, far from the origin): the single-pair query, the
// batched kernel in double and in float against CGAL's exact distance of their corners. The
// facet of A (-) B spanned by two such edges is where the normal equations and the cross
// product of the generators lose 1 / sin^2 and 1 / sin of the angle: the query answered 0.0167
// for boxes 0.0048 apart turned by 1e-6, the float kernel 0.29 for 0.022 (fuzz_kernels).
TEST(ExactOracle, BoxesWithNearlyParallelEdges) {
  std::mt19937_64 rng(83);
  std::uniform_real_distribution<double> u(-1, 1), h(0.3, 1);
  constexpr int kLanes = 16;
  auto A = std::make_unique<BoxBatch<double, kLanes>>(), B = std::make_unique<BoxBatch<double, kLanes>>();
  auto Af = std::make_unique<BoxBatch<float, kLanes>>(), Bf = std::make_unique<BoxBatch<float, kLanes>>();
  auto out = std::make_unique<BoxBoxProximity<double, kLanes>>();
  auto outf = std::make_unique<BoxBoxProximity<float, kLanes>>();
  int checked = 0;
  for (int round = 0; round < test::scaled(8, 2); ++round)
    for (int e = 2; e <= 9; ++e) {
      const double scale = std::pow(10.0, 3 * u(rng));
      Box a[kLanes], b[kLanes];
      for (int k = 0; k < kLanes; ++k) {
        // A above its edge along x at y = z = 0, B below it, B turned about the origin.
        a[k].half_extents = scale * Vector3d(h(rng), h(rng), h(rng));
        b[k].half_extents = scale * Vector3d(h(rng), h(rng), h(rng));
        const double gap = scale * std::pow(10.0, -1 - 4 * (u(rng) + 1) / 2);
        a[k].center = Vector3d(scale * u(rng), a[k].half_extents.y(), a[k].half_extents.z());
        const Eigen::Matrix3d R = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), std::pow(10.0, -e));
        b[k].rotation = R;
        b[k].center = R * Vector3d(scale * u(rng), -b[k].half_extents.y() - gap, -b[k].half_extents.z() - gap);
        const Vector3d shift = 10 * scale * Vector3d(u(rng), u(rng), u(rng));
        a[k].center += shift, b[k].center += shift;
        A->set(k, a[k]), B->set(k, b[k]), Af->set(k, a[k]), Bf->set(k, b[k]);
      }
      A->count = B->count = Af->count = Bf->count = kLanes;
      A->pad(), B->pad(), Af->pad(), Bf->pad();
      box_box_proximity(*A, *B, *out);
      box_box_proximity(*Af, *Bf, *outf);
      for (int k = 0; k < kLanes; ++k) {
        std::vector<Vector3d> pa, pb;
        for (int c = 0; c < 8; ++c) pa.push_back(box_corner(a[k], c)), pb.push_back(box_corner(b[k], c));
        const double exact = peers::cgal_distance(pa, pb);
        Proximity p;
        ASSERT_EQ(proximity(a[k], b[k], p), Status::Ok);
        // The corners' rounding, and the answers' own: a few ulps of the coordinates.
        const double reach = a[k].center.cwiseAbs().maxCoeff() + b[k].center.cwiseAbs().maxCoeff() + 4 * scale;
        const std::string what = "turned by 1e-" + std::to_string(e) + ", lane " + std::to_string(k);
        EXPECT_NEAR(p.distance, exact, 1e-14 * reach) << what;
        EXPECT_NEAR(out->distance[k], exact, 1e-14 * reach) << what;
        // Float: the fast path's certificate allows 64 ulps of |c| + 2 sum h, and the inputs
        // are rounded to float (edges 1e-9 apart in angle merge there, a sliver of 1e-5).
        const double bound = 128 * double(std::numeric_limits<float>::epsilon()) * reach + kSliverThreshold<float> * 2 * scale;
        EXPECT_NEAR(outf->distance[k], exact, bound) << what;
        ++checked;
      }
    }
  EXPECT_GE(checked, 2 * 8 * kLanes);
}

// The stability suite (issue 7): named hard cases (../shared/GUIDE.md section 3), each in
// several variants, through every path (fast, reference, hull; sum and difference). Every result
// must be a valid polytope holding every pairwise sum, with a support function within 1e-12 of
// h_A + h_B; where the input is exactly representable and the structure well defined, V, E and
// F must equal CGAL's exact hull of the pairwise sums; bad input must get a status.
struct HardCase {
  std::string name;
  std::vector<Vector3d> a, b;
  bool exact = false;              // compare the structure with CGAL's exact counts
  double tol = 1e-12;              // containment tolerance, relative to the sum's size
  Status error = Status::Ok;       // the status polytope_from_points must return, if not Ok
  Status sum_status = Status::Ok;  // the status every path must return
};

std::ostream& operator<<(std::ostream& os, const HardCase& c) { return os << c.name; }

std::vector<Vector3d> offset(std::vector<Vector3d> pts, const Vector3d& by) {
  for (auto& p : pts) p += by;
  return pts;
}

std::vector<HardCase> hard_cases() {
  const Vector3d generic = Vector3d(0.3, -0.5, 0.81).normalized();
  const auto cube = scaled(tools::cube_points(), 30 * 7), ico = scaled(tools::exact_icosahedron_points(), 30);
  const auto dod = scaled(tools::exact_dodecahedron_points(), 30);
  const auto R = tools::table1_rotation();
  std::vector<HardCase> c;
  for (const auto& pair : tools::table1_pairs()) c.push_back({"table1_exact_" + pair.name, pair.a, pair.b, true});
  c.push_back({"aligned_boxes_123_plus_half", box({1, 2, 3}), box({0.5, 0.25, 4}), true});
  c.push_back({"aligned_boxes_equal", box({1, 1, 1}), box({1, 1, 1}), true});
  c.push_back({"aligned_boxes_one_thin", box({1, 1, 1e-7}), box({2, 3, 4}), true});
  for (int e = 3; e <= 15; ++e)
    c.push_back({"tiny_rotation_1e-" + std::to_string(e), box({1, 1, 1}),
                 box({1, 1, 1}, tools::axis_angle(generic, std::pow(10.0, -e))), false, 1e-8});
  c.push_back({"rot45_about_z", box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4)), true});
  c.push_back({"rot45_about_x", box({1, 2, 3}), box({1, 1, 1}, tools::axis_angle({1, 0, 0}, M_PI / 4)), false});
  c.push_back(
      {"rot45_about_generic_axis", box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle(generic, M_PI / 4)), false});
  for (double tilt : {1e-6, 1e-9, 1e-12})  // the paper's Fig. 6: edges almost parallel
    c.push_back({"paper_fig6_tilt_" + std::to_string(int(-std::log10(tilt))), box({2, 2, 2}),
                 box({1, 1, 1}, tools::axis_angle(generic, tilt) * tools::axis_angle({0, 0, 1}, M_PI / 2)), false,
                 1e-8});
  const Vector3d far(1e6, -1e6, 1e6);
  c.push_back({"offset_1e6_box_box", offset(box({1, 2, 3}), far), offset(box({1, 1, 1}, R), far)});
  c.push_back({"offset_1e6_icosa_dodeca", offset(tools::icosahedron_points(), far),
               offset(tools::rotated(tools::dodecahedron_points(), R), far)});
  c.push_back({"offset_1e6_box_triangle", offset(box({1, 1, 1}, R), far),
               offset({{0.1, 0.2, 0.3}, {1.1, -0.4, 0.5}, {0.3, 0.9, -0.7}}, far)});
  c.push_back({"scale_1e-6_icosa_tiny_box", tools::icosahedron_points(), box({1e-6, 1e-6, 1e-6}, R)});
  c.push_back({"scale_1e-6_cube_tiny_icosa", box({1, 1, 1}, R), scaled(tools::icosahedron_points(), 1e-6)});
  c.push_back({"scale_1e-6_tiny_triangle_box", {{0, 0, 0}, {1e-6, 0, 0}, {0, 1e-6, 0}}, box({1, 2, 3}, R)});
  for (int axis = 0; axis < 3; ++axis) {
    Vector3d h(30, 30, 30);
    h[axis] = 30e-7;
    c.push_back(
        {"thin_box_1e-7_axis_" + std::to_string(axis), box(h), exact_rotated(scaled(tools::cube_points(), 30)), true});
  }
  // A triangle in the plane of a box face (dyadic coordinates: exact).
  c.push_back({"triangle_on_box_face_top", box({1, 1, 1}), {{-0.5, -0.5, 1}, {0.75, -0.25, 1}, {0.125, 0.5, 1}}, true});
  c.push_back(
      {"triangle_on_box_face_side", box({1, 1, 1}), {{-1, -0.5, -0.5}, {-1, 0.75, -0.25}, {-1, 0.125, 0.5}}, true});
  c.push_back({"triangle_on_box_face_larger", box({1, 1, 1}), {{-4, -4, -1}, {4, -4, -1}, {0, 4, -1}}, true});
  c.push_back({"triangle_triangle_generic",
               {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {{0.25, 0.125, -0.5}, {0.375, 0.25, 0.75}, {-0.5, 0.75, 0.125}},
               true});
  // Two flat operands in parallel planes: the sum is flat, which is not a solid.
  c.push_back({"triangle_triangle_parallel_planes",
               {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {{0.5, 0.5, 1}, {-0.5, 0.25, 1}, {0.25, -0.75, 1}},
               false,
               0,
               Status::Ok,
               Status::DegenerateResult});
  c.push_back({"triangle_triangle_coplanar",
               {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {{2, 0, 0}, {3, 1, 0}, {2, 2, 0}},
               false,
               0,
               Status::Ok,
               Status::DegenerateResult});
  c.push_back({"triangle_triangle_shared_edge_direction",
               {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}},
               {{0, 0, 1}, {2, 0, 1}, {0.5, 0.5, 3}},
               true});
  c.push_back({"identical_cube", exact_rotated(cube), exact_rotated(cube), true});
  c.push_back({"identical_icosahedron", exact_rotated(ico), exact_rotated(ico), true});
  c.push_back({"identical_pyritohedron", exact_rotated(dod), exact_rotated(dod), true});
  for (const auto* shape : {&cube, &ico, &dod}) {
    std::vector<Vector3d> mirrored;
    const auto turned = exact_rotated(*shape);
    for (const auto& p : turned) mirrored.push_back(Vector3d(-p.x(), p.y(), p.z()));
    c.push_back({std::string("mirrored_") + (shape == &cube  ? "cube"
                                             : shape == &ico ? "icosahedron"
                                                             : "pyritohedron"),
                 turned, mirrored, true});
  }
  for (double eps : {0.0, 1e-15, 1e-9}) {
    auto a = tools::icosahedron_points();
    const auto copy = a;
    for (const auto& p : copy) a.push_back(p * (1 + eps));
    c.push_back(
        {eps == 0 ? "duplicated_vertices" : "near_duplicated_vertices_" + std::string(eps == 1e-15 ? "1e-15" : "1e-9"),
         a, tools::rotated(tools::cube_points(), R), false, eps == 1e-9 ? 1e-8 : 1e-12});
  }
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}) {
    auto pts = tools::cube_points();
    pts[5][1] = bad;
    c.push_back({std::string("non_finite_") + (std::isnan(bad) ? "nan"
                                               : bad > 0       ? "inf"
                                                               : "minus_inf"),
                 tools::cube_points(), pts, false, 0, Status::NonFinite});
  }
  auto huge = tools::cube_points();
  huge[2][0] = 1e200;
  c.push_back({"coordinate_beyond_1e100", tools::cube_points(), huge, false, 0, Status::OutOfRange});
  return c;
}

class Stability : public testing::TestWithParam<HardCase> {};

TEST_P(Stability, EveryPathIsValidAndExactWhereDefined) {
  const HardCase& c = GetParam();
  ConvexPolytope A, B;
  const Status sa = polytope_from_points(c.a, A), sb = polytope_from_points(c.b, B);
  if (c.error != Status::Ok) {
    EXPECT_EQ(sa == Status::Ok ? sb : sa, c.error);
    return;
  }
  ASSERT_EQ(sa, Status::Ok);
  ASSERT_EQ(sb, Status::Ok);
  for (double s : {1.0, -1.0}) {
    const peers::ExactCounts exact = c.exact ? peers::exact_counts(c.a, c.b, s) : peers::ExactCounts{};
    for (Method method : {Method::Fast, Method::Reference, Method::Hull}) {
      SCOPED_TRACE(std::string(s > 0 ? "sum " : "difference ") + (method == Method::Fast        ? "fast"
                                                                  : method == Method::Reference ? "reference"
                                                                                                : "hull"));
      MinkowskiSum m;
      const Status st = s > 0 ? minkowski_sum(A, B, m, method) : minkowski_difference(A, B, m, method);
      ASSERT_EQ(st, c.sum_status) << to_string(st);
      if (st != Status::Ok) continue;
      EXPECT_TRUE(test::valid_sum(c.a, c.b, s, A, B, m, c.tol, 1e-12, 300));
      // (The hull method's, and the corrector's, is the exact hull of the sums as doubles.)
      if (c.exact && ((method != Method::Hull && !m.corrected) || test::sums_are_doubles(c.a, c.b, s))) {
        EXPECT_EQ(m.F, exact.F);
        EXPECT_EQ(m.E, exact.E);
        EXPECT_EQ(m.V, exact.V);
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(HardCases, Stability, testing::ValuesIn(hard_cases()),
                         [](const testing::TestParamInfo<HardCase>& info) {
                           std::string name = info.param.name;  // "1e-9" -> "1em9": gtest names are [A-Za-z0-9_]
                           for (char& ch : name) ch = ch == '-' ? 'm' : ch;
                           return name;
                         });

}  // namespace
}  // namespace minksum
