// The Minkowski sum paths (fast, reference, hull) against brute force and against each other.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

#include "support/cgal_peer.hpp"
#include "checks.hpp"
#include "sum/overlay.hpp"
#include "sum/sum_internal.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;
using test::same_sum;
using test::valid_sum;

constexpr Method kMethods[] = {Method::Fast, Method::Reference, Method::Hull};

struct Operands {
  std::vector<Vector3d> a, b;
  ConvexPolytope A, B;
};

Operands make(std::vector<Vector3d> a, std::vector<Vector3d> b) {
  Operands o{std::move(a), std::move(b), {}, {}};
  EXPECT_EQ(polytope_from_points(o.a, o.A), Status::Ok);
  EXPECT_EQ(polytope_from_points(o.b, o.B), Status::Ok);
  return o;
}

// Every method, sum and difference: each result valid; fast == reference when `same`
// (operands whose faces are exactly planar and no near-tie between them: the reference path
// merges within its 1e-9 push); with `exact`, the fast path equals CGAL's exact hull of the
// pairwise sums, facet by facet, and the hull path too where the sums are doubles.
void check_all(const Operands& o, double tol, bool same, MinkowskiSum* fast_sum = nullptr, bool exact = false) {
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m[3];
    for (int k = 0; k < 3; ++k) {
      const Status st =
          s > 0 ? minkowski_sum(o.A, o.B, m[k], kMethods[k]) : minkowski_difference(o.A, o.B, m[k], kMethods[k]);
      ASSERT_EQ(st, Status::Ok) << to_string(st);
      EXPECT_TRUE(valid_sum(o.a, o.b, s, o.A, o.B, m[k], tol, 1e-12, 300)) << "method " << k << " sign " << s;
    }
    EXPECT_FALSE(m[0].corrected) << "the fast path needed the corrector";
    if (same) {
      EXPECT_TRUE(same_sum(m[0], m[1], 1e-9)) << "fast vs reference, sign " << s;
    }
    if (exact) {
      EXPECT_TRUE(test::equals_exact_hull(o.a, o.b, s, m[0], 1e-9)) << "fast vs exact, sign " << s;
      // (The hull method's is the exact hull of the sums as doubles, the result's vertices.)
      if (test::sums_are_doubles(o.a, o.b, s))
        EXPECT_TRUE(test::equals_exact_hull(o.a, o.b, s, m[2], 1e-9)) << "hull vs exact, sign " << s;
    }
    if (fast_sum && s > 0) *fast_sum = m[0];
  }
}

// The pairs in exact coordinates, where every path gives the exact hull; and B turned in
// floating point instead, its faces planar only within rounding: the exact hull of its points
// splits them into triangles, and the fast and hull paths give the exact hull of the pairwise
// sums of those points (the reference path's 1e-9 push merges the triangles again).
TEST(Table1, AllPathsAgreeWithTheExactHullOfThePairwiseSums) {
  for (const auto& pair : tools::table1_pairs()) {
    SCOPED_TRACE(pair.name);
    check_all(make(pair.a, pair.b), 1e-12, true, nullptr, true);
    SCOPED_TRACE("B turned in floating point");
    check_all(make(pair.a, tools::rotated(pair.b_body, tools::table1_rotation())), 1e-12, false, nullptr, true);
  }
}

TEST(Table1, CubeRotatedCubeHasAllThirtyCandidatePlanes) {
  // Generic rotation: 6 + 6 face planes and all 9 edge pairs on both sides, 30 facets.
  const auto pair = tools::table1_pairs()[0];
  MinkowskiSum m;
  check_all(make(pair.a, pair.b), 1e-12, true, &m);
  EXPECT_EQ(m.F, 30);
}

// Seeded random convex polytopes: 4-64 points in a random ellipsoid, rotated and moved.
std::vector<Vector3d> random_points(std::mt19937_64& rng) {
  std::uniform_int_distribution<int> count(4, 64);
  std::uniform_real_distribution<double> u(-1, 1), scale(0.1, 3);
  const int n = count(rng);
  const Vector3d axes(scale(rng), scale(rng), scale(rng)), shift(3 * u(rng), 3 * u(rng), 3 * u(rng));
  const Eigen::Matrix3d R = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3.2 * u(rng));
  std::vector<Vector3d> pts;
  for (const auto& p : tools::sphere_points(n, unsigned(rng()))) pts.push_back(R * p.cwiseProduct(axes) + shift);
  return pts;
}

class RandomPairs : public testing::TestWithParam<int> {};

// 10 shards x 1000 pairs, each as sum and difference; every fourth pair is of 4 to 12 points on
// a half-integer lattice within +-2 (shared planes, parallel edges, coplanar points everywhere),
// where the fast path must give CGAL's exact hull facet by facet.
TEST_P(RandomPairs, FastEqualsReferenceAndBruteForce) {
  std::mt19937_64 rng(1000 + GetParam());
  for (int k = 0; k < test::scaled(1000, 8); ++k) {
    SCOPED_TRACE("shard " + std::to_string(GetParam()) + " pair " + std::to_string(k));
    const bool lattice = k % 4 == 3;
    const Operands o =
        lattice ? make(test::ties::lattice_solid_points(rng, 2, 1), test::ties::lattice_solid_points(rng, 2, 1))
                : make(random_points(rng), random_points(rng));
    for (double s : {1.0, -1.0}) {
      MinkowskiSum fast, ref;
      ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, fast) : minkowski_difference(o.A, o.B, fast), Status::Ok);
      ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, ref, Method::Reference)
                      : minkowski_difference(o.A, o.B, ref, Method::Reference),
                Status::Ok);
      ASSERT_TRUE(valid_sum(o.a, o.b, s, o.A, o.B, fast, 1e-9, 1e-12, 1000, unsigned(k)));
      ASSERT_FALSE(fast.corrected);
      ASSERT_TRUE(same_sum(fast, ref, 1e-9));
      if (lattice) ASSERT_TRUE(test::equals_exact_hull(o.a, o.b, s, fast, 0));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Shards, RandomPairs, testing::Range(0, 10));

// The sizes of the Scaling benchmark, where the overlay walks B's support along every arc of A
// and climbs to the face normals: no crossing missed (the corrector would run), and the hull of
// the pairwise sums (random points on spheres are far from degenerate): CGAL's exact hull facet
// by facet up to 128 points, and at every size the vertices of CGAL's hull of the rounded sums.
TEST(LargePairs, FastEqualsTheExactHullWithoutTheCorrector) {
  for (int n : {24, 32, 128, 256, 512, 1024}) {
    if (n >= 512 && test::scaled(10) < 10) continue;  // (instrumented, these take minutes; Release runs them)
    SCOPED_TRACE("n = " + std::to_string(n));
    const Operands o = make(tools::sphere_points(n, 7u * unsigned(n)), tools::sphere_points(n, 7u * unsigned(n) + 1));
    MinkowskiSum fast;
    ASSERT_EQ(minkowski_sum(o.A, o.B, fast), Status::Ok);
    EXPECT_FALSE(fast.corrected);
    if (n <= 128) EXPECT_TRUE(test::equals_exact_hull(o.a, o.b, 1, fast, 1e-9));
    std::vector<Vector3d> hull;
    peers::cgal_quickhull(o.a, o.b, &hull);
    std::vector<Vector3d> ours;
    for (const auto& v : fast.vertices) ours.push_back(v.point);
    const auto lex = [](const Vector3d& x, const Vector3d& y) {
      return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
    };
    std::sort(hull.begin(), hull.end(), lex), std::sort(ours.begin(), ours.end(), lex);
    ASSERT_EQ(ours.size(), hull.size());
    for (size_t k = 0; k < ours.size(); ++k) EXPECT_LE((ours[k] - hull[k]).norm(), 1e-12) << "vertex " << k;
    EXPECT_TRUE(valid_sum(o.a, o.b, 1, o.A, o.B, fast, 1e-9, 1e-12, 300));
  }
}

// --- The hard cases of GUIDE.md section 3 -------------------------------------------------

std::vector<Vector3d> box_points(const Vector3d& h, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(),
                                 const Vector3d& c = Vector3d::Zero()) {
  std::vector<Vector3d> p;
  for (const auto& q : tools::cube_points()) p.push_back(c + R * q.cwiseProduct(h));
  return p;
}

const Vector3d kGeneric = Vector3d(0.3, -0.5, 0.81).normalized();

// A triangular pyramid whose base is parallel to the faces z = +-1 of a cube, with no edge
// parallel to the cube's.
std::vector<Vector3d> pyramid_points() {
  std::vector<Vector3d> p = {Vector3d(0, 0, -1)};
  for (int k = 0; k < 3; ++k) p.emplace_back(std::cos(0.1 + 2.1 * k), std::sin(0.1 + 2.1 * k), 0);
  return p;
}

// The overlay (overlay.cpp) answers the generic Table 1 pairs (exact coordinates) and random
// pairs of up to 64 points (every fourth checked) with CGAL's exact hull of the pairwise sums (an independent
// construction), never through the corrector; and pairs with parallel faces or edges (where facets merge) with the
// merged facets the reference path finds, without the corrector too.
TEST(Overlay, AnswersGenericPairsLikeTheExactHullAndMergesTies) {
  for (const auto& pair : tools::table1_pairs()) {
    SCOPED_TRACE(pair.name);
    const Operands o = make(pair.a, pair.b);
    MinkowskiSum fast;
    ASSERT_EQ(minkowski_sum(o.A, o.B, fast), Status::Ok);
    ASSERT_FALSE(fast.corrected);
    EXPECT_TRUE(test::equals_exact_hull(o.a, o.b, 1, fast, 1e-9));
    EXPECT_TRUE(valid_sum(o.a, o.b, 1, o.A, o.B, fast, 1e-12, 1e-12, 300));
  }
  std::mt19937_64 rng(77);
  for (int k = 0; k < test::scaled(2000); ++k) {
    SCOPED_TRACE("pair " + std::to_string(k));
    const Operands o = make(random_points(rng), random_points(rng));
    MinkowskiSum fast;
    ASSERT_EQ(minkowski_sum(o.A, o.B, fast), Status::Ok);
    ASSERT_FALSE(fast.corrected);
    if (k % 4 == 0) ASSERT_TRUE(test::equals_exact_hull(o.a, o.b, 1, fast, 1e-9));  // (Epeck: the cost)
    ASSERT_TRUE(valid_sum(o.a, o.b, 1, o.A, o.B, fast, 1e-9, 1e-12, 300, unsigned(k)));
  }
  // Parallel faces (an axis-aligned cube and a box, a cube and itself turned about z) and
  // parallel edges; a face parallel to a face of the cube with no edge parallel to one of its
  // edges (a tie in the support alone: the facet is the sum of the two faces).
  check_all(make(box_points(Vector3d(1, 1, 1)), box_points(Vector3d(0.5, 2, 3))), 1e-12, true);
  check_all(
      make(box_points(Vector3d(1, 1, 1)), box_points(Vector3d(1, 1, 1), tools::axis_angle(Vector3d(0, 0, 1), 0.3))),
      1e-12, true);
  check_all(make(box_points(Vector3d(1, 1, 1)), pyramid_points()), 1e-12, true);
}

// The small overlay's tables (overlay_small.cpp) against the walks, on one placed pair: every
// normal located alike and the same crossings, each with its side. Random pairs of 4 ... 16
// points, B turned by a random rotation (every sign certain: the tables answer), sums and
// differences; and pairs of integer points, some in a common pose, where ties are many and the
// tables must decline (a sign they cannot decide) or agree.
TEST(Overlay, SmallTablesLocateAsTheWalks) {
  std::mt19937_64 rng(2026);
  std::uniform_int_distribution<int> small_int(-3, 3);
  std::uniform_real_distribution<double> u(-1, 1);
  int answered = 0, declined = 0;
  for (int k = 0; k < test::scaled(800); ++k) {
    SCOPED_TRACE("pair " + std::to_string(k));
    const bool ties = k % 2 == 1;
    std::vector<Vector3d> a, b;
    if (ties) {
      for (int n = 0; n < 12; ++n) a.emplace_back(small_int(rng), small_int(rng), small_int(rng));
      for (int n = 0; n < 12; ++n) b.emplace_back(small_int(rng), small_int(rng), small_int(rng));
    } else {
      for (auto* p : {&a, &b})
        for (int n = 4 + int(rng() % 13); n > 0; --n) p->emplace_back(u(rng), 0.5 * u(rng), 2 * u(rng));
    }
    ConvexShape sa, sb;
    if (shape_from_points(a, sa) != Status::Ok || shape_from_points(b, sb) != Status::Ok) continue;  // (flat)
    const detail::ShapeData &da = *detail::ShapeAccess::data(sa), &db = *detail::ShapeAccess::data(sb);
    if (!detail::small_overlay_fits(da, db)) continue;
    Eigen::Isometry3d pose_a = Eigen::Isometry3d::Identity(), pose_b = pose_a;
    if (!ties || k % 4 == 1) pose_b.linear() = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3.2 * u(rng));
    const Eigen::Matrix3d relative = pose_a.linear().transpose() * pose_b.linear();
    const bool difference = k % 3 == 0;
    detail::PlacedBuffers buffers[2][2];
    detail::Placed A[2], B[2];
    detail::Overlay overlay[2];  // [0] the walks, [1] the tables where they answer
    for (int w = 0; w < 2; ++w) {
      detail::place(da, pose_a, Eigen::Matrix3d::Identity(), false, buffers[w][0], A[w]);
      detail::place(db, pose_b, relative, difference, buffers[w][1], B[w]);
      ASSERT_TRUE(overlay[w].locate(A[w], B[w], w == 1));
    }
    ASSERT_FALSE(overlay[0].by_tables);
    if (!overlay[1].by_tables) {
      ++declined;
      continue;
    }
    ++answered;
    const auto same = [](const std::vector<detail::Location>& x, const std::vector<detail::Location>& y) {
      return std::equal(x.begin(), x.end(), y.begin(), y.end(),
                        [](const auto& p, const auto& q) { return p.kind == q.kind && p.id == q.id; });
    };
    EXPECT_TRUE(same(overlay[0].a_normals(), overlay[1].a_normals()));
    EXPECT_TRUE(same(overlay[0].b_normals(), overlay[1].b_normals()));
    std::set<std::tuple<int, int, bool>> crossings[2];
    for (int w = 0; w < 2; ++w)
      for (const auto& x : overlay[w].arc_crossings()) crossings[w].emplace(x.ea, x.eb, x.up);
    EXPECT_EQ(crossings[0], crossings[1]);
    EXPECT_EQ(crossings[1].size(), overlay[1].arc_crossings().size());  // (none twice)
  }
  // Both kinds seen: generic pairs answered, ties declined.
  EXPECT_GT(answered, test::scaled(800) / 4) << answered << " answered, " << declined << " declined";
  EXPECT_GT(declined, test::scaled(800) / 8);
}

// The poles' zero components for want of a term (pole_zero_mask, a table over the normals'
// nonzero masks) against the products themselves, for every pattern of zero components.
TEST(Overlay, PoleZeroMaskIsTheProductsWithAZeroFactor) {
  for (int m = 0; m < 64; ++m) {
    const Vector3d l((m & 1) ? 1.5 : 0, (m & 2) ? -2.25 : 0, (m & 4) ? 0.75 : 0);
    const Vector3d r((m & 8) ? -1.25 : 0, (m & 16) ? 3.5 : 0, (m & 32) ? 2.0 : 0);
    int expected = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = (k + 1) % 3, b = (k + 2) % 3;  // component k of l x r: l_a r_b - l_b r_a
      if (l[a] * r[b] == 0 && l[b] * r[a] == 0) expected |= 1 << k;
    }
    EXPECT_EQ(int(detail::pole_zero_mask(detail::nonzero_mask(l), detail::nonzero_mask(r))), expected) << m;
  }
}

// A polytope built by hand that breaks the Edge contract (one edge's faces swapped, so its
// arc runs the wrong way round): it is not a valid shape (InvalidMesh), and the convenience
// entry, which prepares it, still gives the true sum (the corrector's, from the vertices). Every
// edge of A, and of B, of every Table 1 pair.
TEST(Overlay, RejectsEdgesAgainstTheirContract) {
  for (const auto& pair : tools::table1_pairs()) {
    SCOPED_TRACE(pair.name);
    const Operands o = make(pair.a, pair.b);
    MinkowskiSum truth;
    ASSERT_EQ(minkowski_sum(o.A, o.B, truth), Status::Ok);
    for (int side = 0; side < 2; ++side)
      for (size_t e = 0; e < (side ? o.B : o.A).edges.size(); ++e) {
        SCOPED_TRACE("side " + std::to_string(side) + " edge " + std::to_string(e));
        ConvexPolytope a = o.A, b = o.B;
        Edge& edge = (side ? b : a).edges[e];
        std::swap(edge.left, edge.right);
        ConvexShape shape;
        EXPECT_EQ(shape_from_polytope(side ? b : a, shape), Status::InvalidMesh);
        EXPECT_TRUE(shape.empty());
        MinkowskiSum m;
        ASSERT_EQ(minkowski_sum(a, b, m), Status::Ok);
        EXPECT_TRUE(m.corrected);
        EXPECT_TRUE(same_sum(m, truth, 1e-12));
      }
  }
}

// The box-box kernel path against the general fast path (and both against brute force):
// random pairs, aligned ones (parallel edges: the general path), tiny rotations, and boxes far
// from the origin.
TEST(BoxSum, KernelPathEqualsTheGeneralPath) {
  std::mt19937_64 rng(12);
  int kernel = 0, generic = 0;
  for (int k = 0; k < test::scaled(2000); ++k) {
    Box a = tools::random_box(rng, 2), b = tools::random_box(rng, 2);
    if (k % 10 == 1) b.rotation = a.rotation;
    if (k % 10 == 2) b.rotation = tools::axis_angle(kGeneric, std::pow(10.0, -1 - k % 12)) * a.rotation;
    if (k % 10 == 3) a.center += Vector3d(1e6, -2e6, 3e5), b.center += Vector3d(-1e6, 1e6, 1e6);
    if (k % 10 == 4) std::tie(a, b) = test::ties::touching_boxes(rng);  // tie-heavy (tests/ties)
    if (k % 10 == 5) a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
    const bool aligned = k % 10 == 1 || k % 10 == 2 || k % 10 == 4 || k % 10 == 5;
    ConvexPolytope A, B;
    ASSERT_EQ(polytope_from_box(a, A), Status::Ok);
    ASSERT_EQ(polytope_from_box(b, B), Status::Ok);
    MinkowskiSum got, want;
    ASSERT_EQ(minkowski_sum(a, b, got), Status::Ok);
    ASSERT_EQ(minkowski_sum(A, B, want), Status::Ok);
    ASSERT_TRUE(same_sum(got, want, 1e-9)) << "pair " << k;
    if (!aligned) ++generic, kernel += got.method == Method::Kernel;
    if (k % 10 == 4 || k % 10 == 5)
      ASSERT_TRUE(test::equals_exact_hull(A.vertices, B.vertices, 1, got, 0)) << "pair " << k;
    if (k % 50 == 0) ASSERT_TRUE(valid_sum(A.vertices, B.vertices, 1, A, B, got, 1e-12, 1e-12, 200)) << "pair " << k;
  }
  EXPECT_EQ(kernel, generic);  // the kernel's result stands for every generic pair
  Box bad;
  bad.half_extents.x() = -1;
  MinkowskiSum m;
  EXPECT_EQ(minkowski_sum(bad, Box{}, m), Status::InvalidBox);
}

TEST(HardCases, AlignedBoxes) {
  MinkowskiSum m;
  check_all(make(box_points({1, 2, 3}), box_points({0.5, 0.25, 4})), 1e-12, true, &m);
  EXPECT_EQ(m.F, 6);  // every edge cross vanishes: the sum is again a box
  EXPECT_EQ(m.V, 8);
}

TEST(HardCases, TinyRotations) {
  for (double angle : {1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13, 1e-15}) {
    SCOPED_TRACE(angle);
    // The structure is near-degenerate: the reference path's 1e-9 push merges what the exact
    // hull keeps apart; the fast and hull paths are the exact hull of the rounded corners (the
    // oracle matches vertices within 1e-9: below 1e-7 rad the sum's vertices are closer).
    check_all(make(box_points({1, 1, 1}), box_points({1, 1, 1}, tools::axis_angle(kGeneric, angle))), 1e-8, false,
              nullptr, angle >= 1e-7);
  }
}

TEST(HardCases, FortyFiveDegreesAboutAnAxis) {
  // About z the merged facets are exact in doubles: 8 side facets, top and bottom merged.
  MinkowskiSum m;
  check_all(make(box_points({1, 1, 1}), box_points({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4))), 1e-12, true,
            &m);
  EXPECT_EQ(m.F, 10);
  check_all(make(box_points({1, 1, 1}), box_points({1, 1, 1}, tools::axis_angle(kGeneric, M_PI / 4))), 1e-12, false,
            nullptr, true);
}

TEST(HardCases, PaperFigure6NearParallelEdges) {
  // Two cubes whose edges are almost but not quite parallel (the paper's Fig. 6 failure):
  // a 90-degree turn about z followed by a 1e-9 tilt.
  const Eigen::Matrix3d R = tools::axis_angle(kGeneric, 1e-9) * tools::axis_angle({0, 0, 1}, M_PI / 2);
  check_all(make(box_points({2, 2, 2}), box_points({1, 1, 1}, R)), 1e-8, false);
}

TEST(HardCases, CoordinatesOffsetByAMillion) {
  const Vector3d far(1e6, -1e6, 1e6);
  check_all(make(box_points({1, 2, 3}, Eigen::Matrix3d::Identity(), far),
                 box_points({1, 1, 1}, tools::table1_rotation(), far)),
            1e-12, false, nullptr, true);
}

TEST(HardCases, ScaleRatioOneInAMillion) {
  check_all(make(tools::icosahedron_points(), box_points({1e-6, 1e-6, 1e-6}, tools::table1_rotation())), 1e-12, false);
}

TEST(HardCases, BoxWithHalfExtentTenToTheMinusSeven) {
  check_all(make(box_points({1, 1, 1e-7}), box_points({1, 1, 1}, tools::table1_rotation())), 1e-12, false, nullptr,
            true);
}

TEST(HardCases, TriangleCoplanarWithABoxFace) {
  const std::vector<Vector3d> tri = {{-0.5, -0.5, 1}, {0.7, -0.2, 1}, {0.1, 0.6, 1}};
  MinkowskiSum m;
  check_all(make(box_points({1, 1, 1}), tri), 1e-12, true, &m);
  // The box's faces (the triangle's sides merge into top and bottom) and one vertical
  // parallelogram per triangle edge; the CGAL oracle test checks the same count exactly.
  EXPECT_EQ(m.F, 6 + 3);
}

TEST(HardCases, BoxPlusGenericTriangleIsASolid) {
  const std::vector<Vector3d> tri = {{0.1, 0.2, 0.3}, {1.1, -0.4, 0.5}, {0.3, 0.9, -0.7}};
  check_all(make(box_points({1, 2, 0.5}, tools::table1_rotation()), tri), 1e-12, false, nullptr, true);
}

TEST(HardCases, TrianglePlusTriangle) {
  const std::vector<Vector3d> t1 = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<Vector3d> t2 = {{0.2, 0.1, -0.5}, {0.3, 0.2, 0.7}, {-0.4, 0.8, 0.1}};
  // In doubles 0.1 + 0.2 is not 0.3: the exact sum has a sliver (9 facets) that the decimal
  // coordinates meant to be a tie, and that the reference's 1e-9 push merges (7). The fast
  // path is the exact hull of the pairwise sums of the doubles given.
  const Operands o = make(t1, t2);
  check_all(o, 1e-12, false);
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, m) : minkowski_difference(o.A, o.B, m), Status::Ok);
    EXPECT_TRUE(test::equals_exact_hull(o.a, o.b, s, m, 1e-12)) << "sign " << s;
  }
}

TEST(HardCases, CoplanarTrianglesGiveAFlatSum) {
  const Operands o = make({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{2, 0, 0}, {3, 1, 0}, {2, 2, 0}});
  for (Method method : kMethods) {
    MinkowskiSum m;
    EXPECT_EQ(minkowski_sum(o.A, o.B, m, method), Status::DegenerateResult);
  }
}

TEST(HardCases, IdenticalAndMirroredPolytopes) {
  const auto d = tools::table1_pairs()[4].b;  // (exact: a rounded dodecahedron's faces would split)
  MinkowskiSum m;
  check_all(make(d, d), 1e-12, true, &m);
  EXPECT_EQ(m.F, 12);  // A (+) A = 2A
  std::vector<Vector3d> mirrored;
  for (const auto& p : d) mirrored.push_back(Vector3d(-p.x(), p.y(), p.z()));
  check_all(make(d, mirrored), 1e-12, false);
}

TEST(HardCases, DuplicatedAndNearDuplicatedVertices) {
  auto a = tools::icosahedron_points();
  const auto copy = a;
  a.insert(a.end(), copy.begin(), copy.end());
  for (const auto& p : copy) a.push_back(p * (1 + 1e-15));
  check_all(make(a, tools::rotated(tools::cube_points(), tools::table1_rotation())), 1e-12, false);
}

// The fast path (polytopes, and shapes at identity poses), sum and difference, against brute
// force; `exact_enough`: it needs no corrector.
void check_fast(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, bool exact_enough) {
  const Operands o = make(a, b);
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m, posed;
    ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, m) : minkowski_difference(o.A, o.B, m), Status::Ok);
    EXPECT_TRUE(valid_sum(a, b, s, o.A, o.B, m, 1e-12, 1e-12, 300)) << "sign " << s;
    ASSERT_EQ(s > 0 ? minkowski_sum(SA, I, SB, I, posed) : minkowski_difference(SA, I, SB, I, posed), Status::Ok);
    EXPECT_TRUE(valid_sum(a, b, s, SA.polytope(), SB.polytope(), posed, 1e-12, 1e-12, 300)) << "shapes, sign " << s;
    if (exact_enough) EXPECT_FALSE(m.corrected || posed.corrected) << "sign " << s;
  }
}

// Fuzz finding (fuzz_sum, seed 31): a crossing of a short arc (faces 1.6e-14 rad apart) with an
// arc whose edge is parallel to its edge to 1e-71. The parallelogram's normal came from the
// rounded poles' cross product, whose sign was noise there: a facet turned inside out, a
// pairwise sum 0.7 size beyond it. (Coordinates 4e71 against units.)
TEST(HardCases, CrossingOfAShortArcWithAParallelEdge) {
  const double L = 4.2525583765009148e+71, M = 4.2525583765008447e+71;
  check_fast({{0, 1, 0}, {-L, 1, 0}, {0, 0, -L}, {-L, -L, -L}, {0, -M, -L}}, {{-L, 0, 197}, {-L, -L, -L}, {1, 1, 0}},
             true);
}

// Fuzz finding (fuzz_sum, seed 32): a sliver tetrahedron whose adjacent faces nearly oppose
// (dihedral angle 2.6e-10), so the poles rounded from its normals are off by 4e-6 rad, and a
// triangle's normal 7e-8 rad inside one cell was placed in its neighbour: a support off by 1e-7
// of the size. Such maps (ShapeData::support_error) have their results certified.
TEST(HardCases, SliverWithNearlyOpposedFaces) {
  const double L = 4.2525583765009148e+71;
  check_fast({{256, 8.3885719050467071e-308, -4}, {0, 0.03125, 0}, {-L, -200, 0}, {-L, -197.640625, -L}},
             {{1.1210841918420029e-71, -L, -4.2525583780818657e+71},
              {-L, 199.390625, 196.765625},
              {-L, -4.2525587812305062e+71, -196.78125},
              {0, 1.8699346191297772e-307, -L}},
             false);
}

// The reference and hull paths at mixed scales (a point of 1e2 plus one of 1e81 rounds to the
// latter): the hull is of the sums as doubles (e71b900), so both answer Ok with a valid sum.
void check_hull_paths(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
  const Operands o = make(a, b);
  for (double s : {1.0, -1.0})
    for (Method method : {Method::Reference, Method::Hull}) {
      MinkowskiSum m;
      const Status st = s > 0 ? minkowski_sum(o.A, o.B, m, method) : minkowski_difference(o.A, o.B, m, method);
      ASSERT_EQ(st, Status::Ok) << to_string(st) << ", sign " << s;
      EXPECT_TRUE(valid_sum(o.a, o.b, s, o.A, o.B, m, 1e-12, 1e-12, 300)) << "sign " << s;
    }
}

// Fuzz finding (fuzz_sum, seed 1207001, after 415,919 inputs): a sliver reaching 4.3e71 among
// small points, whose hull has two facets 1.6e-8 rad apart. Qhull merged them into one
// 4-vertex facet that was planar only to 1e-8 rad, and the fast sum's facet built on it stood
// 9.6e73 (4.8e-8 of the size) off its own plane. The exact hull keeps the two facets. The
// reference and hull paths then gave a facet a zero normal (its corners' Newell normal at 1e81
// overflowed when squared, and its rounded corners span no plane). (Not
// compared with the exact hull of the pairwise sums: a small point plus one at 1e81 rounds to
// the large one, so the sum's doubles cannot keep every exact vertex apart.)
TEST(HardCases, FacetsOfASliverNotCoplanarStayApart) {
  const double X = 0x1.ececececececep+237, Y = 0x1.0d0d0d0d0d0dp+270;
  const std::vector<Vector3d> a = {{0, 0x1.94p+3, 8},
                                   {0x1.48p-1, 256, 0},
                                   {0, 1, 0x1.ccp+8},
                                   {0x1.69p+8, 0, -200},
                                   {-X, -X, 0x1.1313131313132p-396},
                                   {-X, -X, -X},
                                   {-X, -0x1.ececece3fcecep+237, 0x0.0008000cececep-1022},
                                   {0, -512, -512},
                                   {-256, 256, 0},
                                   {0, 256, 0},
                                   {-512, 256, 0},
                                   {0, 0, -512},
                                   {0, -0x1.5cp+8, -200}};
  const std::vector<Vector3d> b = {{0x1.8988p+7, 0x1.8988p+7, 0x0.0000000000001p-1022},
                                   {-X, -0x1.ececece4dcecep+237, -X},
                                   {-X, -0x1.0d0d0d0d0d0cep+270, -Y},
                                   {-Y, -Y, -Y}};
  check_fast(a, b, false);
  check_hull_paths(a, b);
}

// Fuzz findings (fuzz_sum, seeds 1207008 and 1207010, after 390 and 376 inputs): points at 1e71
// beside small ones, whose sum the hull corrector rebuilds. The corrector's hull was the exact
// hull of the exact pairwise sums, whose facets their rounding does not keep planar (a sum of
// 1e2 and 1e71 rounds to the latter): with the Newell normals of the rounded corners a pairwise
// sum stood 4.3e71 (half the size) outside a plane of a fast sum; with normals of the exact
// sums to 106 bits, 1.2e65 outside one of a reference sum. It is now the exact hull of the
// sums as doubles, the result's vertices.
TEST(HardCases, CorrectorPlanesOfSumsThatRound) {
  const double X = 0x1.ececececececep+237, Y = -0x1.797cp+8;
  const std::vector<Vector3d> a = {{0, 0x1.8p-5, 0x1.48p+7},
                                   {0, 0, 0},
                                   {256, 0, 0x1.0008p+8},
                                   {1.5, 0, -0x1p-6},
                                   {-0x1.ece00000000ffp+237, -X, 0x1.131313132cecep-236},
                                   {-0x1.8ec8p+7, -X, -X},
                                   {-X, -X, 0x1.133cecece3fcep-236},
                                   {0x1.8988p+7, 0x0.0000000000001p-1022, -X},
                                   {Y, Y, Y}};
  const std::vector<Vector3d> b = {{-0x1.8af8p+7, -X, -X}, {-X, 0x0.000000000004p-1022, 0}, {0, 0, 0}};
  const Operands o = make(a, b);  // (as polytopes: shape_from_points declines A's slivers)
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, m) : minkowski_difference(o.A, o.B, m), Status::Ok);
    EXPECT_TRUE(valid_sum(a, b, s, o.A, o.B, m, 1e-12, 1e-12, 300)) << "sign " << s;
  }
  check_hull_paths(a, b);
}

TEST(HardCases, ReferenceCorrectorPlaneOfSumsThatRound) {
  const double X = 0x1.ececececececep+237, H = 0x1.8988p+8, G = -0x1.e9fp+7;
  const std::vector<Vector3d> a = {{1, 3, 1},
                                   {10, 0, 1},
                                   {9, 4, -0x1p-6},
                                   {0, 0, 0x1p-6},
                                   {0x1p-5, 0x1p-6, 0},
                                   {0, 1, 0},
                                   {0, 0, 0},
                                   {0, 0, -400},
                                   {-0x1.2c2c2ce24cecep+45, G, G},
                                   {G, G, G},
                                   {G, G, 0x1.4818p+7},
                                   {0x1.88p+1, 0x1.fep+1, 0},
                                   {0x0.0c4032903cecep-1022, -0x1.ececep+237, -X},
                                   {-0x1.700cececececep+234, -X, -0x1.ecececeffffcep+237},
                                   {-X, H, H},
                                   {H, H, H}};
  const std::vector<Vector3d> b = {{H, H, H},
                                   {H, H, -0x1.899p+7},
                                   {-0x1.13133cecececep+228, -X, -0x1.700cececececep+234},
                                   {-X, -0x1.ecececeffffcep+237, -0x1.e31d9323131cep+237},
                                   {-0x1.0cecececececep+227, -0x1.eceffffffffcep+237, -X},
                                   {-X, 0x0.00000000000cep-1022, 0},
                                   {0, 0, 0}};
  check_hull_paths(a, b);
}

// Fuzz finding (fuzz_sum, seed 1207011, after 71,786 inputs): edges at 4e71 and 1.3e84, whose
// cross product (5e155) and the product of their squared lengths overflow when squared. The
// overlay's crossing facets took the infinite c2 for a length and scaled their normals by
// 1 / sqrt(inf): three zero normals, which pass every other check (no point is outside a plane
// of normal 0 and offset 0). Polytopes and posed shapes (the fuzzer's), both signs.
TEST(HardCases, CrossingNormalsOfEdgesWhoseCrossOverflows) {
  const double X = 0x1.ececececececep+237, S = 0x1.4544p+8;
  const std::vector<Vector3d> a = {{S, S, S},
                                   {-0x1.ecececece2fcep+237, -X, -X},
                                   {S, S, -X},
                                   {-0x1.acecececececep+236, 0x1.0506p+9, -0x1.ececececece31p+237}};
  const std::vector<Vector3d> b = {{-X, -X, -0x1.ececececeeecep+237}, {2 * S, S, 0x1.1515151ff5bffp+278}, {S, S, S}};
  const Operands o = make(a, b);
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  Eigen::Isometry3d turn = Eigen::Isometry3d::Identity();  // a quarter turn about z: exact
  turn.linear() << 0, -1, 0, 1, 0, 0, 0, 0, 1;
  std::vector<Vector3d> ta, tb;
  for (const Vector3d& p : a) ta.push_back(turn * p);
  for (const Vector3d& p : b) tb.push_back(turn * p);
  const Operands t = make(ta, tb);
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m, posed;
    ASSERT_EQ(s > 0 ? minkowski_sum(o.A, o.B, m, Method::Fast) : minkowski_difference(o.A, o.B, m, Method::Fast),
              Status::Ok);
    EXPECT_TRUE(valid_sum(a, b, s, o.A, o.B, m, 1e-12, 1e-12, 300)) << "sign " << s;
    ASSERT_EQ(s > 0 ? minkowski_sum(SA, turn, SB, turn, posed) : minkowski_difference(SA, turn, SB, turn, posed),
              Status::Ok);
    EXPECT_TRUE(valid_sum(ta, tb, s, t.A, t.B, posed, 1e-12, 1e-12, 300)) << "posed, sign " << s;
  }
}

// Fuzz finding (fuzz_sum, seed 1207014, after 547,940 inputs): A has two faces whose unit
// normals round to the same double (the exact hull keeps them apart), so one of its Gauss-map
// arcs is a point. A crossing there fell to near_parallel_normal, which built a circle from the
// arc's two ends: a zero frame, and a normal 6e-17 long.
TEST(HardCases, CrossingAnArcOfFacesWhoseNormalsRoundAlike) {
  const double X = 0x1.ececececececep+237, T = 0x1.5555555555555p-1, U = -0x1.5555555555554p-2;
  const std::vector<Vector3d> a = {{0x1.48p-1, 256, 0},
                                   {0, 1, 0x1.ccp+8},
                                   {0x1.00ccp+8, 1.5, 0},
                                   {-X, -0x1.ececece39cecep+237, -X},
                                   {-X, -X, -0x1.ecece3fcececep+237},
                                   {0, 0x1.88p+7, -0x1.8ec8p+7}};
  const std::vector<Vector3d> b = {{0, 0, 0}, {0x1.88p+7, 0x1.5018p+7, -20}, {0x1.ececececececep-211, 0x1.d988p+7, 0}};
  Eigen::Isometry3d pb = Eigen::Isometry3d::Identity();  // (the fuzzer's pose: a turn about (1, 1, 1))
  pb.linear() << U, T, T, T, U, T, T, T, U;
  pb.translation() = Vector3d(-X, 0x0.000cececece3fp-1022, 0);
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  std::vector<Vector3d> wb;
  for (const Vector3d& q : SB.polytope().vertices) wb.push_back(pb * q);
  // (The posed sum rounds its vertices otherwise than a + s (pb b): checked to 1e-9 of the size,
  // as fuzz_sum does, with unit normals.)
  for (double s : {1.0, -1.0}) {
    MinkowskiSum m;
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    ASSERT_EQ(s > 0 ? minkowski_sum(SA, I, SB, pb, m) : minkowski_difference(SA, I, SB, pb, m), Status::Ok);
    const double tol = 1e-9 * 2 * X;
    for (int f = 0; f < m.F; ++f) {
      const SumPlane& pl = m.planes[size_t(f)];
      EXPECT_NEAR(pl.normal.norm(), 1, 1e-12) << "sign " << s << " facet " << f;
      for (const Vector3d& p : SA.polytope().vertices)
        for (const Vector3d& q : wb) EXPECT_LE(pl.normal.dot(p + s * q), pl.offset + tol) << "facet " << f;
      for (int v : m.facet(f)) EXPECT_NEAR(pl.normal.dot(m.vertices[size_t(v)].point), pl.offset, tol);
    }
  }
}

// Fuzz finding (fuzz_sum, seed 53102, after 313,889 inputs): 20 points flat to 4e-12 of their
// size, a triangle 4.1e13 across, turned, on a small polytope whose top edge is level to
// 6.5e-12 rad. The triangle's normal leaned on a point 246 off its plane (1.2e-11 rad), which
// put it in the wrong cell of B's map; A's arc crosses B's at 0.004 rad, so the crossing moved
// 1.7e-9 rad along it: a facet that does not exist, a pairwise sum 68,000 (1.65e-9 of the size)
// outside it. A flat polygon's normal is now its loop's own. The structure must be the exact
// hull's.
TEST(HardCases, NearTieThroughAShallowCrossing) {
  const std::vector<Vector3d> a = {{1, 3, 1},
                                   {10, 0, 1},
                                   {9, 4, -0.015625},
                                   {0, 0, 0.015625},
                                   {0.03125, 0.015625, 0},
                                   {0, 1, 0},
                                   {0, 0, 0.03125},
                                   {-41255782948253.609, -244.96875, -245.96875},
                                   {-244.96875, -244.96875, -244.96875},
                                   {-244.96875, -244.96875, -512},
                                   {2, 0, 0},
                                   {-200, -41212452817309.609, -244.96875},
                                   {-245.96875, -244.96875, 64.25},
                                   {0, -512, 256},
                                   {256, 256, -512},
                                   {0, 256, 0}};
  const std::vector<Vector3d> b = {{256, 0, 0},           {0, 424, 425.65625},       {425.65625, 425.65625, 425.65625},
                                   {0.765625, 0.03125, 0}, {0.015625, 0.03125, 0}, {0.015625, 0.015625, 0.03125}};
  ConvexShape SA, SB;
  ASSERT_EQ(shape_from_points(a, SA), Status::Ok);
  ASSERT_EQ(shape_from_points(b, SB), Status::Ok);
  Eigen::Isometry3d pa = Eigen::Isometry3d::Identity(), pb = pa;
  pa.linear() = pb.linear() = Vector3d(-1, 1, -1).asDiagonal();
  pa.translation() = Vector3d(0.015625, 0.03125, 0), pb.translation() = Vector3d(0.015625, 0, 0.03125);
  std::vector<Vector3d> wa, wb;
  for (const auto& p : SA.polytope().vertices) wa.push_back(pa * p);
  for (const auto& q : SB.polytope().vertices) wb.push_back(pb * q);
  MinkowskiSum m;
  ASSERT_EQ(minkowski_sum(SA, pa, SB, pb, m), Status::Ok);
  EXPECT_TRUE(test::equals_exact_hull(wa, wb, 1, m, 0));  // (every input and sum here is a double)
}

TEST(HardCases, NonFiniteInputIsRejected) {
  for (double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    auto pts = tools::cube_points();
    pts[3].y() = bad;
    ConvexPolytope p;
    EXPECT_EQ(polytope_from_points(pts, p), Status::NonFinite);
    Box b;
    b.center.x() = bad;
    EXPECT_EQ(polytope_from_box(b, p), Status::NonFinite);
    EXPECT_EQ(polytope_from_triangle({{0, 0, 0}, {1, bad, 0}, {0, 1, 0}}, p), Status::NonFinite);
  }
}

TEST(Sum, EmptyOperandIsAnError) {
  ConvexPolytope empty, cube;
  ASSERT_EQ(polytope_from_points(tools::cube_points(), cube), Status::Ok);
  MinkowskiSum m;
  EXPECT_EQ(minkowski_sum(empty, cube, m), Status::TooFewPoints);
  EXPECT_EQ(minkowski_difference(cube, empty, m), Status::TooFewPoints);
}

TEST(Sum, DifferenceContainsTheOriginExactlyWhenBoxesOverlap) {
  // A (-) B is the configuration-space obstacle. Oracle: the separating axis theorem on the 15
  // axes of two boxes, evaluated on the raw vertices.
  // One pair in 4 is tie-heavy (tests/ties): lattice boxes, or boxes in exact contact, where the
  // origin lies on A (-) B's boundary and touching counts as overlapping (offset >= 0).
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  int overlaps = 0, on_boundary = 0;
  for (int k = 0; k < 500; ++k) {
    Box ba, bb;
    ba.half_extents = Vector3d(1, 0.5, 0.3), bb.half_extents = Vector3d(0.4, 0.9, 0.6);
    ba.rotation = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
    bb.rotation = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
    bb.center = 2.2 * Vector3d(u(rng), u(rng), u(rng));
    if (k % 8 == 7) std::tie(ba, bb) = test::ties::touching_boxes(rng);
    if (k % 8 == 3) ba = test::ties::lattice_box(rng, 2, 1), bb = test::ties::lattice_box(rng, 2, 1);
    const Eigen::Matrix3d &Ra = ba.rotation, &Rb = bb.rotation;
    const auto a = test::ties::corners(ba), b = test::ties::corners(bb);
    const Operands o = make(a, b);
    MinkowskiSum m;
    ASSERT_EQ(minkowski_difference(o.A, o.B, m), Status::Ok);
    double least = 1e300;
    for (const auto& p : m.planes) least = std::min(least, p.offset);
    const bool inside = least >= 0;
    on_boundary += least == 0;
    std::vector<Vector3d> axes;
    for (int i = 0; i < 3; ++i) {
      axes.push_back(Ra.col(i));
      axes.push_back(Rb.col(i));
      for (int j = 0; j < 3; ++j) axes.push_back(Ra.col(i).cross(Rb.col(j)));
    }
    bool separated = false;
    for (const auto& n : axes) {
      double amin = 1e300, amax = -1e300, bmin = 1e300, bmax = -1e300;
      for (const auto& p : a) amin = std::min(amin, n.dot(p)), amax = std::max(amax, n.dot(p));
      for (const auto& p : b) bmin = std::min(bmin, n.dot(p)), bmax = std::max(bmax, n.dot(p));
      separated = separated || amax < bmin || bmax < amin;
    }
    EXPECT_EQ(inside, !separated) << "pose " << k;
    overlaps += !separated;
  }
  EXPECT_GT(overlaps, 50);  // both outcomes are exercised
  EXPECT_LT(overlaps, 450);
  EXPECT_GE(on_boundary, 500 / 8);  // (and every pair in exact contact)
}

// The assembly's consistency check (which sends results to the corrector) must reject a
// reversed facet, a missing facet and a repeated facet, and accept the real thing.
TEST(Sum, AssemblyRejectsInconsistentFacets) {
  ConvexPolytope a, b;  // a tetrahedron (+) a point-like tiny tetrahedron: pairs (i, 0) only
  ASSERT_EQ(polytope_from_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, a), Status::Ok);
  ASSERT_EQ(polytope_from_points({{0, 0, 0}, {1e-3, 0, 0}, {0, 1e-3, 0}, {0, 0, 1e-3}}, b), Status::Ok);
  auto loops = [&](bool reverse_one, bool drop_one, bool repeat_one) {
    std::vector<detail::FacetLoop> f;
    for (const auto& face : a.faces) {
      detail::FacetLoop l{face.normal, {}};
      for (int v : face.loop) l.loop.emplace_back(v, 0);
      f.push_back(l);
    }
    if (reverse_one) std::reverse(f[0].loop.begin(), f[0].loop.end());
    if (drop_one) f.pop_back();
    if (repeat_one) f.push_back(f[0]);
    return f;
  };
  MinkowskiSum m;
  auto ok = [&](std::vector<detail::FacetLoop> f) {
    detail::assemble(a.vertices, b.vertices, f, m);
    return m.euler_ok;
  };
  EXPECT_TRUE(ok(loops(false, false, false)));
  EXPECT_FALSE(ok(loops(true, false, false)));
  EXPECT_FALSE(ok(loops(false, true, false)));
  EXPECT_FALSE(ok(loops(false, false, true)));
}

}  // namespace
}  // namespace minksum
