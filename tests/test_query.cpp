// Proximity queries against brute force: vertex-face and edge-edge enumeration for the distance,
// the separating axis theorem over face normals and edge crosses for overlap and penetration,
// all vertex pairs for the maximum distance.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <tuple>
#include <vector>

#include "simd/box_pair_data.hpp"
#include "checks.hpp"
#include "exact_distance.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

// Largest distance of p outside the polytope's face planes (0 inside).
double outside(const ConvexPolytope& P, const Vector3d& p) {
  double worst = 0;
  for (const auto& f : P.faces) worst = std::max(worst, f.normal.dot(p) - f.offset);
  return worst;
}

// `exact_gap` (>= 0 for lattice operands) is the exact distance between the surfaces
// (ties::exact_surface_gap): then the verdict must be exact, and the distance at contact exactly 0.
void expect_agrees(const ConvexPolytope& A, const ConvexPolytope& B, const Proximity& got, const std::string& what,
                   double exact_gap = -1) {
  const test::Oracle o = test::brute_force(A, B);
  double size = 1;
  for (const auto* P : {&A, &B})
    for (const auto& v : P->vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  const double tol = 1e-9 * size;
  if (exact_gap >= 0) {
    // Surfaces of lattice operands that do not meet are far apart next to rounding (the squared
    // distance is a ratio of small integers), so brute force's containment verdict is sure there.
    const bool meet = exact_gap == 0 || o.overlap;
    ASSERT_EQ(got.intersecting, meet) << what << ": exact surface gap " << exact_gap;
    if (meet)
      EXPECT_EQ(got.distance, 0.0) << what;
    else
      EXPECT_NEAR(got.distance, exact_gap, tol) << what;
  } else if (o.distance > tol || o.depth > tol) {
    // Touching within rounding may be reported either way; a real gap or overlap may not.
    ASSERT_EQ(got.intersecting, o.overlap) << what;
  }
  EXPECT_NEAR(got.distance, o.distance, tol) << what;
  EXPECT_NEAR(got.max_distance, o.max_distance, tol) << what;
  EXPECT_NEAR(got.penetration_depth, o.depth, tol) << what;
  // The witnesses lie on A and B, and realise the distance (or the penetration).
  EXPECT_LE(outside(A, got.point_a), tol) << what;
  EXPECT_LE(outside(B, got.point_b), tol) << what;
  if (!got.intersecting)
    EXPECT_NEAR((got.point_a - got.point_b).norm(), got.distance, tol) << what;
  else
    EXPECT_LE((got.point_a - got.point_b - got.penetration_depth * got.penetration_direction).norm(), tol)
        << what << ": depth " << got.penetration_depth << " along " << got.penetration_direction.transpose()
        << ", witnesses " << got.point_a.transpose() << " and " << got.point_b.transpose();
  EXPECT_NEAR((got.far_a - got.far_b).norm(), got.max_distance, tol) << what;
}

// Every 16th case of RandomQueries is tie-heavy (tests/ties): lattice operands (half-integer
// coordinates, quarter-turned boxes), every other one of them in exact contact; every 64th for
// polytopes of up to 12 points (the exact surface distance is the cost there).
bool lattice_case(int k) { return k % 16 == 15; }
bool touching_case(int k) { return k % 32 == 31; }
bool lattice_polytopes(int k) { return k % 64 == 63; }

class RandomQueries : public testing::TestWithParam<int> {};

// 100,000 pairs of each kind (10 shards of 10,000), half of them overlapping or close; 1 in 16
// (polytopes: 1 in 64) on the lattice.
TEST_P(RandomQueries, BoxBoxAgreesWithBruteForce) {
  std::mt19937_64 rng(100 + GetParam());
  for (int k = 0; k < test::scaled(10000, 64); ++k) {
    Box a = tools::random_box(rng, 1.5), b = tools::random_box(rng, 1.5);
    if (k % 8 == 0) b.rotation = a.rotation;  // parallel generators
    if (touching_case(k))
      std::tie(a, b) = test::ties::touching_boxes(rng);
    else if (lattice_case(k))
      a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
    Proximity got;
    ASSERT_EQ(proximity(a, b, got, Want::All), Status::Ok);
    ConvexPolytope A, B;
    polytope_from_box(a, A), polytope_from_box(b, B);
    expect_agrees(A, B, got, "box-box pair " + std::to_string(k),
                  lattice_case(k) ? test::ties::exact_surface_gap(A, B) : -1);
    if (testing::Test::HasFailure()) return;
  }
}

TEST_P(RandomQueries, BoxTriangleAgreesWithBruteForce) {
  std::mt19937_64 rng(200 + GetParam());
  for (int k = 0; k < test::scaled(10000, 64); ++k) {
    Box a = tools::random_box(rng, 1.5);
    Triangle t = tools::random_triangle(rng, 1.5);
    if (touching_case(k))
      std::tie(a, t) = test::ties::touching_box_triangle(rng);
    else if (lattice_case(k))
      a = test::ties::lattice_box(rng, 2, 1), t = test::ties::lattice_triangle(rng, 2, 1);
    Proximity got;
    ASSERT_EQ(proximity(a, t, got, Want::All), Status::Ok);
    ConvexPolytope A, B;
    polytope_from_box(a, A), polytope_from_triangle(t, B);
    expect_agrees(A, B, got, "box-triangle pair " + std::to_string(k),
                  lattice_case(k) ? test::ties::exact_surface_gap(A, B) : -1);
    if (testing::Test::HasFailure()) return;
  }
}

TEST_P(RandomQueries, TriangleTriangleAgreesWithBruteForce) {
  std::mt19937_64 rng(300 + GetParam());
  for (int k = 0; k < test::scaled(10000, 64); ++k) {
    Triangle s = tools::random_triangle(rng, 1.2), t = tools::random_triangle(rng, 1.2);
    if (touching_case(k))
      std::tie(s, t) = test::ties::touching_triangles(rng);
    else if (lattice_case(k))
      s = test::ties::lattice_triangle(rng, 2, 1), t = test::ties::lattice_triangle(rng, 2, 1);
    Proximity got;
    ASSERT_EQ(proximity(s, t, got, Want::All), Status::Ok);
    ConvexPolytope A, B;
    polytope_from_triangle(s, A), polytope_from_triangle(t, B);
    expect_agrees(A, B, got, "triangle-triangle pair " + std::to_string(k),
                  lattice_case(k) ? test::ties::exact_surface_gap(A, B) : -1);
    if (testing::Test::HasFailure()) return;
  }
}

TEST_P(RandomQueries, PolytopePolytopeAgreesWithBruteForce) {
  std::mt19937_64 rng(400 + GetParam());
  std::uniform_int_distribution<int> count(4, 24);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < test::scaled(10000, 64); ++k) {
    ConvexPolytope A, B;
    for (auto* P : {&A, &B}) {
      std::vector<Vector3d> pts;
      if (lattice_polytopes(k)) {
        const Vector3d shift = P == &B ? test::ties::lattice_point(rng, 4, 1) : Vector3d::Zero();
        for (const auto& p : test::ties::lattice_solid_points(rng, 2, 1)) pts.push_back(p + shift);
      } else {
        const Vector3d c = 1.5 * Vector3d(u(rng), u(rng), u(rng));
        for (const auto& p : tools::sphere_points(count(rng), unsigned(rng()))) pts.push_back(c + p);
      }
      ASSERT_EQ(polytope_from_points(pts, *P), Status::Ok);
    }
    Proximity got;
    ASSERT_EQ(proximity(A, B, got, Want::All), Status::Ok);
    expect_agrees(A, B, got, "polytope pair " + std::to_string(k),
                  lattice_polytopes(k) ? test::ties::exact_surface_gap(A, B) : -1);
    if (testing::Test::HasFailure()) return;
  }
}

INSTANTIATE_TEST_SUITE_P(Shards, RandomQueries, testing::Range(0, 10));

// `want` selects what is computed: each level's fields equal Want::All's (bit for bit: the
// box pair's verdict, depth and distance come from the same separating axis test and walk) and
// the fields past it keep their defaults; the farthest pair alone likewise. The patch's
// witnesses may differ from the plain witnesses (either is a closest pair), so Witnesses is
// checked against Patch on the distance, and its points for being a closest pair. Random and
// tie-heavy pairs.
TEST(Query, WantSelectsTheFields) {
  std::mt19937_64 rng(91);
  const auto same_verdict = [](const Proximity& got, const Proximity& all) { return got.intersecting == all.intersecting; };
  const auto same_distance = [](const Proximity& got, const Proximity& all) {
    return got.distance == all.distance && got.penetration_depth == all.penetration_depth &&
           got.penetration_direction == all.penetration_direction;
  };
  // Apart, the levels below the patch take GJK's point as A's witness and the patch the level
  // sets' point: their distances, each the one its witnesses realise, differ by rounding.
  const auto near_distance = [](const Proximity& got, const Proximity& all) {
    return std::abs(got.distance - all.distance) <= 1e-12 * (1 + all.distance) &&
           got.penetration_depth == all.penetration_depth && got.penetration_direction == all.penetration_direction;
  };
  const auto same_points = [](const Proximity& got, const Proximity& all) {
    return got.point_a == all.point_a && got.point_b == all.point_b;
  };
  const auto same_far = [](const Proximity& got, const Proximity& all) {
    return got.max_distance == all.max_distance && got.far_a == all.far_a && got.far_b == all.far_b;
  };
  const Proximity none;
  int overlapping = 0;
  for (int k = 0; k < 400; ++k) {
    // Every fourth pair on the integer lattice (tests/ties.hpp): faces on faces, exact touching.
    const bool tie = k % 4 == 3;
    const Box box = tie ? test::ties::lattice_box(rng, 2, 1) : tools::random_box(rng, 1.0);
    const Box other = tie ? test::ties::lattice_box(rng, 2, 1) : tools::random_box(rng, 1.0);
    const Triangle s = tie ? test::ties::lattice_triangle(rng, 2, 1) : tools::random_triangle(rng, 1.0);
    const Triangle t = tie ? test::ties::lattice_triangle(rng, 2, 1) : tools::random_triangle(rng, 1.0);
    ConvexPolytope A, B;
    ASSERT_EQ(polytope_from_box(box, A), Status::Ok);
    ASSERT_EQ(polytope_from_box(other, B), Status::Ok);
    const auto check = [&](const auto& query, const char* what) {
      Proximity all, verdict, distance, witnesses, patch, far, plain;
      ASSERT_EQ(query(all, Want::All), Status::Ok);
      ASSERT_EQ(query(verdict, Want::Verdict), Status::Ok);
      ASSERT_EQ(query(distance, Want::Distance), Status::Ok);
      ASSERT_EQ(query(witnesses, Want::Witnesses), Status::Ok);
      ASSERT_EQ(query(patch, Want::Patch), Status::Ok);
      ASSERT_EQ(query(far, Want::MaxDistance), Status::Ok);
      ASSERT_EQ(query(plain, Want::Witnesses | Want::MaxDistance), Status::Ok);
      const std::string where = std::string(what) + " pair " + std::to_string(k);
      EXPECT_TRUE(same_verdict(verdict, all) && same_distance(verdict, none) && same_points(verdict, none) &&
                  same_far(verdict, none)) << where;
      EXPECT_TRUE(same_verdict(distance, all) && near_distance(distance, all) && same_distance(distance, witnesses) &&
                  same_points(distance, none) && same_far(distance, none)) << where;
      EXPECT_TRUE(same_verdict(witnesses, all) && near_distance(witnesses, all) && same_far(witnesses, none)) << where;
      EXPECT_TRUE(same_verdict(patch, all) && same_distance(patch, all) && same_points(patch, all) &&
                  same_far(patch, none)) << where;
      EXPECT_TRUE(same_far(far, all) && same_verdict(far, none) && same_distance(far, none) && same_points(far, none))
          << where;
      EXPECT_TRUE(same_far(plain, all) && same_distance(plain, witnesses) && same_points(plain, witnesses)) << where;
      // The plain witnesses are a closest pair: as far apart as the distance (apart), on the
      // boxes' surfaces either way (within rounding of their coordinates).
      if (!all.intersecting) EXPECT_NEAR((witnesses.point_b - witnesses.point_a).norm(), all.distance, 1e-12) << where;
      EXPECT_GT(all.max_distance, 0) << where;
      overlapping += all.intersecting;
    };
    check([&](Proximity& p, Want w) { return proximity(box, other, p, w); }, "box-box");
    check([&](Proximity& p, Want w) { return proximity(box, t, p, w); }, "box-triangle");
    check([&](Proximity& p, Want w) { return proximity(s, t, p, w); }, "triangle-triangle");
    check([&](Proximity& p, Want w) { return proximity(A, B, p, w); }, "polytope");
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(overlapping, 200);  // both kinds of answer are covered
  EXPECT_LT(overlapping, 1400);
}

// The allocation-free box-triangle and triangle-triangle paths against the general path, a
// different algorithm (the origin's Voronoi region on the polytope A (-) B): random pairs, and
// pairs made hard on purpose (a triangle in a box face's plane, inside the box, coplanar
// triangles, near-parallel ones, far from the origin, and one in 7 tie-heavy: a box and a
// triangle in exact contact, a lattice triangle).
TEST(SmallShapes, AgreeWithTheGeneralPath) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto agree = [](const Proximity& got, const Proximity& want, double size, const std::string& what,
                        bool ties = false) {
    const double tol = 1e-9 * size;
    // (On lattice operands the verdict is exact: both paths must give the same, within rounding too.)
    if (ties || want.distance > tol || want.penetration_depth > tol)
      ASSERT_EQ(got.intersecting, want.intersecting) << what;
    if (ties && want.intersecting) EXPECT_EQ(got.distance, 0.0) << what;
    EXPECT_NEAR(got.distance, want.distance, tol) << what;
    EXPECT_NEAR(got.penetration_depth, want.penetration_depth, tol) << what;
    EXPECT_NEAR(got.max_distance, want.max_distance, tol) << what;
  };
  int overlapping = 0;
  for (int k = 0; k < test::scaled(20000); ++k) {
    const double scale = k % 5 == 4 ? 1e6 : 1;
    const Vector3d offset = k % 5 == 4 ? Vector3d(3e6, -2e6, 1e6) : Vector3d::Zero();
    Box box = tools::random_box(rng, 1.5);
    box.center = scale * box.center + offset, box.half_extents *= scale;
    Triangle t = tools::random_triangle(rng, 1.5), s = tools::random_triangle(rng, 1.5);
    for (Triangle* x : {&t, &s})
      x->a = scale * x->a + offset, x->b = scale * x->b + offset, x->c = scale * x->c + offset;
    if (k % 7 == 1) {  // t in the plane of the box's +x face
      const Vector3d n = box.rotation.col(0), p = box.center + box.half_extents[0] * n;
      for (Vector3d* c : {&t.a, &t.b, &t.c}) *c -= n.dot(*c - p) * n;
    }
    if (k % 7 == 2) {  // t inside the box
      const Vector3d* c[3] = {&t.a, &t.b, &t.c};
      for (int i = 0; i < 3; ++i)
        *const_cast<Vector3d*>(c[i]) =
            box.center + box.rotation * (0.5 * box.half_extents.cwiseProduct(Vector3d(u(rng), u(rng), u(rng))));
    }
    if (k % 7 == 3) {  // s coplanar with t
      const Vector3d n = (t.b - t.a).cross(t.c - t.a).normalized();
      for (Vector3d* c : {&s.a, &s.b, &s.c}) *c -= n.dot(*c - t.a) * n;
    }
    if (k % 7 == 4) {  // s nearly parallel to t, 1e-3 above it
      const Vector3d n = (t.b - t.a).cross(t.c - t.a).normalized();
      for (Vector3d* c : {&s.a, &s.b, &s.c}) *c -= (n.dot(*c - t.a) - 1e-3 * scale * (1 + 1e-9 * u(rng))) * n;
    }
    const bool ties = k % 7 == 5;  // a box and a triangle in exact contact, a lattice triangle (tests/ties)
    if (ties) std::tie(box, t) = test::ties::touching_box_triangle(rng), s = test::ties::lattice_triangle(rng, 2, 1);
    if (check_triangle(t) != Status::Ok || check_triangle(s) != Status::Ok) continue;
    ConvexPolytope B, T, S;
    ASSERT_EQ(polytope_from_box(box, B), Status::Ok);
    ASSERT_EQ(polytope_from_triangle(t, T), Status::Ok);
    ASSERT_EQ(polytope_from_triangle(s, S), Status::Ok);
    const double size = scale * 4 + offset.norm();
    Proximity got, want;
    ASSERT_EQ(proximity(box, t, got), Status::Ok);
    ASSERT_EQ(proximity(B, T, want), Status::Ok);
    agree(got, want, size, "box-triangle " + std::to_string(k), ties);
    if (ties) EXPECT_TRUE(got.intersecting) << "touching box-triangle " << k;
    overlapping += got.intersecting;
    ASSERT_EQ(proximity(t, s, got), Status::Ok);
    ASSERT_EQ(proximity(T, S, want), Status::Ok);
    agree(got, want, size, "triangle-triangle " + std::to_string(k), ties);
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(overlapping, test::scaled(20000) / 10);
}

// --- Hard cases -----------------------------------------------------------------------------

Box box_at(const Vector3d& c, const Vector3d& h = Vector3d::Ones(),
           const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity()) {
  Box b;
  b.center = c, b.half_extents = h, b.rotation = R;
  return b;
}

Proximity query(const Box& a, const Box& b) {
  Proximity p;
  EXPECT_EQ(proximity(a, b, p), Status::Ok);
  return p;
}

TEST(QueryHardCases, TouchingFacesAreIntersectingAtDistanceZero) {
  const Proximity p = query(box_at({0, 0, 0}), box_at({2, 0.3, -0.2}));
  EXPECT_TRUE(p.intersecting);
  EXPECT_EQ(p.distance, 0);
  EXPECT_EQ(p.penetration_depth, 0);
}

TEST(QueryHardCases, TouchingEdges) {
  const Eigen::Matrix3d R = tools::axis_angle({0, 0, 1}, M_PI / 4);
  // B's vertical edge at x = 1 + sqrt(2) - sqrt(2) touches A's face x = 1.
  const Proximity p = query(box_at({0, 0, 0}), box_at({1 + std::sqrt(2.0), 0, 0}, Vector3d::Ones(), R));
  EXPECT_NEAR(p.distance, 0, 1e-15);
  EXPECT_NEAR(p.penetration_depth, 0, 1e-15);
}

TEST(QueryHardCases, ParallelFacesWithAGap) {
  const Proximity p = query(box_at({0, 0, 0}), box_at({0.5, 0.25, 2.75}));
  EXPECT_FALSE(p.intersecting);
  EXPECT_NEAR(p.distance, 0.75, 1e-15);
  EXPECT_NEAR(p.point_a.z(), 1, 1e-15);
  EXPECT_NEAR(p.point_b.z(), 1.75, 1e-15);
}

TEST(QueryHardCases, OneBoxInsideTheOther) {
  const Proximity p = query(box_at({0, 0, 0}, {3, 3, 3}), box_at({0.5, 0, 0}, {0.5, 0.5, 0.5}));
  EXPECT_TRUE(p.intersecting);
  EXPECT_NEAR(p.penetration_depth, 3, 1e-15);  // push B out through A's +x face: 3 - 0.5 + 0.5
  EXPECT_NEAR(p.penetration_direction.x(), 1, 1e-15);
}

TEST(QueryHardCases, IdenticalBoxes) {
  const Box b = box_at({1, 2, 3}, {0.5, 1, 2}, tools::table1_rotation());
  const Proximity p = query(b, b);
  EXPECT_TRUE(p.intersecting);
  EXPECT_NEAR(p.penetration_depth, 1.0, 1e-12);  // twice the smallest half extent
}

TEST(QueryHardCases, TinyGapsAndPenetrations) {
  for (double gap : {1e-9, -1e-9}) {
    const Proximity p = query(box_at({0, 0, 0}), box_at({2 + gap, 0.1, 0.2}));
    EXPECT_EQ(p.intersecting, gap < 0);
    EXPECT_NEAR(p.distance, std::max(gap, 0.0), 1e-15);
    EXPECT_NEAR(p.penetration_depth, std::max(-gap, 0.0), 1e-15);
  }
}

TEST(QueryHardCases, CoordinatesAtAMillion) {
  const Vector3d far(1e6, -1e6, 1e6);
  const Proximity p =
      query(box_at(far), box_at(far + Vector3d(2.5, 0.5, 0.25), Vector3d::Ones(), tools::axis_angle({0, 0, 1}, 0.0)));
  EXPECT_NEAR(p.distance, 0.5, 1e-9);
}

// Found by fuzzing: a box with half extents of 1e-312 (at 1e-300 from the origin) next to a box
// of 200 got a NaN distance (its generators square to zero). A speck's distance to a box is
// the point's (analytic, by clamping in the box's frame); a pair at 1e90 answers as the same
// pair scaled by 2^-300.
TEST(QueryHardCases, SpecksAndHugeBoxes) {
  std::mt19937_64 rng(44);
  std::uniform_real_distribution<double> u(-3, 3);
  for (int k = 0; k < test::scaled(2000); ++k) {
    Box big = tools::random_box(rng, 0.5);
    big.center += Vector3d(u(rng), u(rng), u(rng));
    Box speck;  // valid: its extents are not small next to its own coordinates
    speck.center = Vector3d(1e-300, -2e-300, 0);
    speck.half_extents = Vector3d(1e-312, 2e-312, 1e-311);
    const Vector3d local = big.rotation.transpose() * (speck.center - big.center);
    const double want = (local.cwiseAbs() - big.half_extents).cwiseMax(0.0).norm();
    Proximity p;
    ASSERT_EQ(proximity(speck, big, p), Status::Ok);
    ASSERT_NEAR(p.distance, want, 1e-12) << "pair " << k;
    ASSERT_TRUE(p.point_a.allFinite() && p.point_b.allFinite() && std::isfinite(p.max_distance));
    Box a = tools::random_box(rng, 1), b = tools::random_box(rng, 1);
    Proximity small, huge, tiny;
    ASSERT_EQ(proximity(a, b, small), Status::Ok);
    // Subnormal pairs (a fuzz finding: the power-of-two scale overflowed and gave NaN); their
    // coordinates keep about 34 bits at 2^-1040.
    const double g = std::ldexp(1.0, -1040);
    Box ta = a, tb = b;
    for (Box* x : {&ta, &tb}) x->center *= g, x->half_extents *= g;
    ASSERT_EQ(proximity(ta, tb, tiny), Status::Ok);
    ASSERT_TRUE(tiny.point_a.allFinite() && tiny.point_b.allFinite() && std::isfinite(tiny.max_distance));
    ASSERT_NEAR(tiny.distance / g, small.distance, 1e-8) << "pair " << k;
    ASSERT_NEAR(tiny.max_distance / g, small.max_distance, 1e-8) << "pair " << k;
    const double f = std::ldexp(1.0, 300);
    for (Box* x : {&a, &b}) x->center *= f, x->half_extents *= f;
    ASSERT_EQ(proximity(a, b, huge), Status::Ok);
    ASSERT_EQ(huge.intersecting, small.intersecting) << "pair " << k;
    ASSERT_NEAR(huge.distance / f, small.distance, 1e-12) << "pair " << k;
    ASSERT_NEAR(huge.penetration_depth / f, small.penetration_depth, 1e-12) << "pair " << k;
    ASSERT_NEAR(huge.max_distance / f, small.max_distance, 1e-12) << "pair " << k;
  }
}

// A sliver tetrahedron reaching 1e86 and a triangle 250 across, apart by 2.9e76 (2e-10 of the
// coordinates) by the exact triangle distance over their faces (GMP): apart. Seen along the
// sliver face's normal they lie within `touching` of one level, and the triangle's point lies
// in the wedge beyond the face's corner of 2e-10 rad (within the tolerance of both its edges'
// lines, 2.9e76 from the face): "touching".
//  - ci/fuzz, seed 211248740: the point beyond the corner's wedge, outside an edge's line;
//  - fuzz_query campaign, seed 71207, 925,017 inputs (the tetrahedron posed, the triangle
//    still): the point's side of both lines is rounding (192 and 6e66 from them, the face's
//    coordinates 1e86), and both said inside; `holds` counted that as inside the polygon.
TEST(QueryHardCases, ASliverFaceDoesNotReachBeyondItsCorner) {
  const std::vector<Vector3d> sliver = {{0, -192.765625, -1.2362992417415827e+86},
                                        {-2.7854136467034274e+44, -1.3847039131408324e+86, 2.8486404963689082e-306},
                                        {-192.765625, -2.8777739825156522e+76, -1.0223906992179551e+62},
                                        {-2.8777739825156522e+76, -1.3847039131046474e+86, -1.091914959381939e-309}};
  const std::vector<Vector3d> b = {{-256, 0, 0}, {244.953125, 244.953125, 244.953125}, {0, 244.953125, 244.953125}};
  const std::vector<Vector3d> c = {{0, 0, 0}, {0, 252, 0}, {0, 0, 128.9375}};
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity(), from = Eigen::Isometry3d::Identity();
  pose.matrix() << -0.31548058450582195, -0.30510371016843307, 0.89854533933537362, -0.036915471378945415,
      0.92872050154670116, -0.29366524397983207, 0.22636023167753985, 1.9669144346901535, 0.19480818978346029,
      0.90590973640850236, 0.37600175355118909, 2.9118735400436537, 0, 0, 0, 1;
  from.matrix() << -0.099027118238702166, 0.99150742663447367, -0.08430096548689732, 3.328378486852531,
      -0.99100078990859231, -0.090598703095013153, 0.09853582799190222, 191.23691350153527, 0.090061447100777764,
      0.093300042476874137, 0.99155637147866105, 161.42958105848732, 0, 0, 0, 1;
  ConvexShape S, B, C;
  ASSERT_EQ(shape_from_points(sliver, S), Status::Ok);
  ASSERT_EQ(shape_from_points(b, B), Status::Ok);
  ASSERT_EQ(shape_from_points(c, C), Status::Ok);
  for (const auto& [A, other, at] : {std::tuple{&S, &B, pose}, std::tuple{&C, &S, from}}) {
    ConvexPolytope placed = other->polytope();  // (the faces' least exact distance: GMP)
    for (Vector3d& v : placed.vertices) v = at * v;
    const double exact = test::ties::exact_surface_gap(A->polytope(), placed);
    ASSERT_GT(exact, 1e76);
    for (Want want : {Want::Verdict, Want::Witnesses, Want::Patch}) {
      Proximity p;
      ASSERT_EQ(proximity(*A, Eigen::Isometry3d::Identity(), *other, at, p, want), Status::Ok);
      EXPECT_FALSE(p.intersecting) << unsigned(want);
      if (want != Want::Verdict) EXPECT_NEAR(p.distance, exact, 1e-12 * 1.4e86);
    }
  }
}

// The smallest overlap of two boxes over the 15 axes, as an oracle independent of the library's
// separating axis test: each axis from the boxes' columns as given, the corners' projections
// in binary128 (the cross of two doubles is exact there), divided by the axis's length at the
// end, so a nearly parallel edge pair's axis is as accurate as a face's.
double overlap_of_corners(const Box& a, const Box& b) {
  using Q = __float128;
  const auto corners = [](const Box& x, Q (&out)[8][3]) {
    for (int k = 0; k < 8; ++k)
      for (int d = 0; d < 3; ++d) {
        out[k][d] = Q(x.center[d]);
        for (int i = 0; i < 3; ++i) out[k][d] += Q((k >> i & 1) ? 1 : -1) * Q(x.half_extents[i]) * Q(x.rotation(d, i));
      }
  };
  Q ca[8][3], cb[8][3];
  corners(a, ca), corners(b, cb);
  std::vector<std::array<Q, 3>> axes;
  for (const Box* x : {&a, &b})
    for (int i = 0; i < 3; ++i) axes.push_back({Q(x->rotation(0, i)), Q(x->rotation(1, i)), Q(x->rotation(2, i))});
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const auto &u = axes[i], &v = axes[3 + j];
      axes.push_back({u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]});
    }
  long double least = INFINITY;
  for (const auto& n : axes) {
    const Q len2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    if (len2 == 0) continue;
    Q lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int s = 0; s < 2; ++s)
      for (const auto& c : s ? cb : ca) {
        const Q t = n[0] * c[0] + n[1] * c[1] + n[2] * c[2];
        lo[s] = t < lo[s] ? t : lo[s], hi[s] = t > hi[s] ? t : hi[s];
      }
    const Q overlap = hi[0] - lo[1] < hi[1] - lo[0] ? hi[0] - lo[1] : hi[1] - lo[0];
    least = std::min(least, static_cast<long double>(overlap) / std::sqrt(static_cast<long double>(len2)));
  }
  return static_cast<double>(least);
}

// fuzz_query campaign, seed 20261208, 415,906 inputs: a slab (470 x 1.8 x 470) and a cube 470
// on one centre, turned 1e-8 apart. Edge axes of nearly parallel edges (|L| = 4e-11) came from
// the separating axis test's frame-relative formulas, which err by eps (|c| + sum h) / |L|: one
// read 471.65596 where no axis is below 471.6562547, and the query answered that depth. Pairs
// turned 1e-4 ... 1e-10.5 rad about nearly the slab's normal, against the corners' overlaps (binary128); the
// single-pair query and the batched kernel of every ISA.
TEST(QueryHardCases, NearlyParallelEdgesDoNotUndercutTheDepth) {
  std::vector<std::pair<Box, Box>> pairs;
  Box a, b;
  a.center = b.center = Vector3d::Constant(469.828125);
  a.half_extents = {469.828125, 1.828125, 469.828125}, b.half_extents = Vector3d::Constant(469.828125);
  a.rotation << -0x1.5552d7f8c266cp-2, -0x1.56e8a55477e5dp-1, 0x1.53c0c6a7e94d9p-1, 0x1.53c0c6a7e94d9p-1,
      0x1.5552d7f8c2668p-2, 0x1.56e8a55477e5dp-1, -0x1.56e8a55477e5dp-1, 0x1.53c0c6a7e94d9p-1, 0x1.5552d7f8c2668p-2;
  b.rotation << -0x1.5552d7f933f59p-2, -0x1.56e8a51b77bap-1, 0x1.53c0c6e1547d9p-1, 0x1.53c0c6a7afff3p-1,
      0x1.5552d86bd1d11p-2, 0x1.56e8a5380eddp-1, -0x1.56e8a554946b2p-1, 0x1.53c0c6c48b1dcp-1, 0x1.5552d7864f721p-2;
  pairs.emplace_back(a, b);
  std::mt19937_64 rng(20261208);
  std::uniform_real_distribution<double> unit(-1, 1), size(0.5, 500);
  for (int k = 0; k < 400; ++k) {
    Box x = tools::random_box(rng, 1.0), y = x;
    x.half_extents = {size(rng), k % 2 ? size(rng) : 1.828125, size(rng)};
    y.half_extents = {size(rng), size(rng), size(rng)};
    if (k % 4 >= 2) y.center += Vector3d(unit(rng), unit(rng), unit(rng));
    // About nearly the slab's normal: the crosses of the nearly parallel edges lie near it, so
    // their overlaps come within rounding of the smallest.
    const double angle = std::pow(10.0, -4 - 6.5 * (k % 40) / 39.0);
    const Vector3d axis = Vector3d::UnitY() + 1e-8 * Vector3d(unit(rng), unit(rng), unit(rng));
    y.rotation = x.rotation * tools::axis_angle(axis, angle);
    pairs.emplace_back(x, y);
  }
  const Isa best = active_isa();
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!force_isa(isa)) continue;
    for (size_t k = 0; k < pairs.size(); ++k) {
      const auto& [x, y] = pairs[k];
      const double want = overlap_of_corners(x, y), tol = 1e-11 * 2000;
      ASSERT_GT(want, 0) << k;
      Proximity p;
      ASSERT_EQ(proximity(x, y, p), Status::Ok);
      EXPECT_NEAR(p.penetration_depth, want, tol) << to_string(isa) << " pair " << k;
      auto X = std::make_unique<BoxBatch<double, kLaneMultiple>>(), Y = std::make_unique<BoxBatch<double, kLaneMultiple>>();
      auto out = std::make_unique<BoxBoxProximity<double, kLaneMultiple>>();
      X->set_one(x), Y->set_one(y);
      box_box_proximity(*X, *Y, *out);
      EXPECT_NEAR(out->depth[0], want, tol) << to_string(isa) << " batched, pair " << k;
      if (testing::Test::HasFailure()) break;
    }
  }
  force_isa(best);
}

TEST(QueryHardCases, CoplanarTriangles) {
  Proximity p;
  ASSERT_EQ(proximity(Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, Triangle{{2, 0, 0}, {3, 0, 0}, {2, 1, 0}}, p),
            Status::Ok);
  EXPECT_FALSE(p.intersecting);
  EXPECT_NEAR(p.distance, 1, 1e-15);
  ASSERT_EQ(proximity(Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, Triangle{{0.2, 0.2, 0}, {3, 0, 0}, {2, 1, 0}}, p),
            Status::Ok);
  EXPECT_TRUE(p.intersecting);
}

// Hypothesis campaign of 51d5905 (seed 1207016): a sliver tetrahedron, flat to 1e-10 of its
// size (its three points at x = -1 lie 2^-24 off a line). Flattened to a triangle, it lost the
// corner (-1, 0, 0), which its pose puts on the unit tetrahedron's corner (1, 0, 0): "2.7e-5
// apart" for shapes that share a point. A shape's vertices are the exact extreme points.
TEST(QueryHardCases, ASliverFlatOnlyToAToleranceKeepsItsCorners) {
  const std::vector<Vector3d> sliver = {{0, -1, -2}, {-1, 0, 0}, {-1, 0, 0x1p-14}, {-1, 0x1p-24, 1}};
  ConvexShape A, B;
  ASSERT_EQ(shape_from_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, A), Status::Ok);
  ASSERT_EQ(shape_from_points(sliver, B), Status::Ok);
  EXPECT_FALSE(B.polytope().flat);
  EXPECT_EQ(B.polytope().vertices.size(), 4u);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Vector3d(-1, 1, -1).asDiagonal();  // (-1, 0, 0) to (1, 0, 0), A's corner
  for (Want want : {Want::Verdict, Want::Witnesses, Want::All}) {
    Proximity p;
    ASSERT_EQ(proximity(A, Eigen::Isometry3d::Identity(), B, pose, p, want), Status::Ok);
    EXPECT_TRUE(p.intersecting) << unsigned(want);
    if (want != Want::Verdict) EXPECT_EQ(p.distance, 0.0) << unsigned(want);
  }
}

TEST(Query, BadInputGetsAStatus) {
  Proximity p;
  Box bad;
  bad.center.y() = std::nan("");
  EXPECT_EQ(proximity(bad, Box{}, p), Status::NonFinite);
  bad = Box{};
  bad.half_extents.z() = 0;
  EXPECT_EQ(proximity(Box{}, bad, p), Status::InvalidBox);
  EXPECT_EQ(proximity(Box{}, Triangle{{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, p), Status::Collinear);
  EXPECT_EQ(proximity(Triangle{{0, 0, 0}, {1, 0, std::numeric_limits<double>::infinity()}, {0, 1, 0}},
                      Triangle{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, p),
            Status::NonFinite);
  ConvexPolytope empty, cube;
  ASSERT_EQ(polytope_from_box(Box{}, cube), Status::Ok);
  EXPECT_EQ(proximity(empty, cube, p), Status::TooFewPoints);
  // Finite but too large to compute with (products would overflow): a status, not a crash.
  bad = Box{};
  bad.center.x() = 256, bad.half_extents.y() = 1e-304;  // corners coincide in double
  EXPECT_EQ(proximity(bad, Box{}, p), Status::InvalidBox);
  bad = Box{};
  bad.center.x() = 1e150;
  EXPECT_EQ(proximity(bad, Box{}, p), Status::OutOfRange);
  EXPECT_EQ(proximity(Box{}, Triangle{{0, 0, 0}, {1e200, 0, 0}, {0, 1, 0}}, p), Status::OutOfRange);
  // A sum read with operands it was not built from, or no sum at all.
  MinkowskiSum m;
  EXPECT_EQ(proximity(m, cube, cube, p), Status::TooFewPoints);
  ConvexPolytope tetra;
  ASSERT_EQ(polytope_from_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, tetra), Status::Ok);
  ASSERT_EQ(minkowski_difference(cube, cube, m), Status::Ok);
  EXPECT_EQ(proximity(m, cube, tetra, p), Status::InvalidMesh);
  EXPECT_EQ(proximity(m, cube, cube, p), Status::Ok);
  EXPECT_TRUE(p.intersecting);
}

TEST(Query, ContainsStopsAtTheFirstSeparatingPlane) {
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_box(Box{}, A), Status::Ok);
  ASSERT_EQ(polytope_from_box(Box{}, B), Status::Ok);
  MinkowskiSum m;
  ASSERT_EQ(minkowski_difference(A, B, m), Status::Ok);
  EXPECT_TRUE(contains(m, Vector3d(1.9, -1.9, 2)));
  EXPECT_FALSE(contains(m, Vector3d(2.1, 0, 0)));
}

// A triangle's corner on the centre of a box's face, one edge running into the box: the least
// depth is along the cross product of that edge, (1, 1, -4) / 2, with the box's x edges,
// -(0, 4, 1) / sqrt(17) (by hand: the box's edge at y = 0.5, z = 1.5 tops it at -3.5 / sqrt(17),
// the triangle's edge bottoms it at -4 / sqrt(17)). The deepest points are where the two edges
// cross, seen along it. (A lattice case of RandomQueries: the witnesses were left at the
// triangle's corner, which realises no penetration, because two crossing edge level sets
// were taken not to meet.)
TEST(QueryHardCases, PenetrationAlongAnEdgeCrossEndsWithTheEdgesCrossing) {
  const Box box = box_at({-1, 2, 2}, {0.5, 1.5, 0.5});
  const Triangle t{{-1, 0.5, 2}, {-0.5, 1, 0}, {-0.5, -1.5, -1}};
  const double depth = 0.5 / std::sqrt(17.0);
  const Vector3d n = -Vector3d(0, 4, 1) / std::sqrt(17.0);
  // The crossing: the box's edge (x, 0.5, 1.5) at x = -1 + 2 / 17, the triangle's edge
  // (-1, 0.5, 2) + s (0.5, 0.5, -2) at s = 4 / 17, which is the box's point less depth n.
  const Vector3d on_box(-1 + 2.0 / 17, 0.5, 1.5), on_triangle = on_box - depth * n;
  ConvexPolytope B, T;
  ASSERT_EQ(polytope_from_box(box, B), Status::Ok);
  ASSERT_EQ(polytope_from_triangle(t, T), Status::Ok);
  Proximity p[3];
  ASSERT_EQ(proximity(box, t, p[0]), Status::Ok);
  ASSERT_EQ(proximity(B, T, p[1]), Status::Ok);
  ASSERT_EQ(proximity(T, B, p[2]), Status::Ok);
  for (int k = 0; k < 3; ++k) {
    const double sign = k == 2 ? -1 : 1;  // (triangle first: the other way round)
    EXPECT_TRUE(p[k].intersecting) << k;
    EXPECT_NEAR(p[k].penetration_depth, depth, 1e-15) << k;
    EXPECT_NEAR((p[k].penetration_direction - sign * n).norm(), 0, 1e-15) << k;
    EXPECT_NEAR((p[k].point_a - (k == 2 ? on_triangle : on_box)).norm(), 0, 1e-14) << k;
    EXPECT_NEAR((p[k].point_b - (k == 2 ? on_box : on_triangle)).norm(), 0, 1e-14) << k;
  }
}

TEST(Query, PenetrationAlongADirection) {
  ConvexPolytope A, B;
  ASSERT_EQ(polytope_from_box(box_at({0, 0, 0}), A), Status::Ok);
  ASSERT_EQ(polytope_from_box(box_at({1.5, 0, 0}), B), Status::Ok);
  MinkowskiSum m;
  ASSERT_EQ(minkowski_difference(A, B, m), Status::Ok);
  EXPECT_NEAR(penetration_along(m, Vector3d(1, 0, 0)), 0.5, 1e-15);   // push B further out
  EXPECT_NEAR(penetration_along(m, Vector3d(-1, 0, 0)), 3.5, 1e-15);  // push it through A
  EXPECT_NEAR(penetration_along(m, Vector3d(0, 1, 0)), 2, 1e-15);
}

}  // namespace
}  // namespace minksum

namespace minksum {
namespace {

// The batched box-box proximity kernel on every ISA, float and double, against the general
// exact path (itself checked against brute force above).
template <class T>
void check_batched_proximity(Isa isa, unsigned seed, double spread) {
  ASSERT_TRUE(force_isa(isa));
  constexpr int N = 1024;
  auto A = std::make_unique<BoxBatch<T, N>>(), B = std::make_unique<BoxBatch<T, N>>();
  auto out = std::make_unique<BoxBoxProximity<T, N>>();
  std::mt19937_64 rng(seed);
  std::vector<Box> as, bs;
  // Hard cases first: aligned and nearly aligned boxes apart along an edge or a corner direction
  // (their closest points lie on merged, parallel generators), 45 degrees, touching, inside.
  std::vector<std::pair<Box, Box>> hard;
  const Vector3d axis = Vector3d(0.3, -0.5, 0.81).normalized();
  for (double angle : {0.0, 1e-12, 1e-9, 1e-6, 1e-3, M_PI / 4, M_PI / 2}) {
    for (const Vector3d& offset : {Vector3d(3, 0.2, 0.1), Vector3d(2.5, 2.5, 0.3), Vector3d(2.6, 2.7, 2.8),
                                   Vector3d(2, 0, 0), Vector3d(0.3, 0.1, 0)}) {
      hard.emplace_back(box_at({0, 0, 0}), box_at(offset, {1, 1, 1}, tools::axis_angle(axis, angle)));
      hard.emplace_back(box_at({0, 0, 0}, {1, 0.5, 0.25}),
                        box_at(offset, {0.5, 1, 0.75}, tools::axis_angle({0, 0, 1}, angle)));
    }
  }
  for (int k = 0; k < N; ++k) {
    Box a = tools::random_box(rng, spread), b = tools::random_box(rng, spread);
    if (k < int(hard.size())) a = hard[k].first, b = hard[k].second;
    // Parallel but not axis-aligned (a facet of A (-) B is then a zonogon of four generators).
    else if (k % 5 == 0)
      b.rotation = a.rotation;
    // Tie-heavy (tests/ties; exact in float too): boxes in exact contact, lattice boxes.
    else if (k % 16 == 7)
      std::tie(a, b) = test::ties::touching_boxes(rng);
    else if (k % 16 == 11)
      a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
    // Round the inputs to T so that both sides see the same boxes.
    for (Box* x : {&a, &b}) {
      x->center = x->center.cast<T>().template cast<double>();
      x->half_extents = x->half_extents.cast<T>().template cast<double>();
    }
    as.push_back(a), bs.push_back(b);
    A->set(k, a), B->set(k, b);
  }
  A->count = B->count = N;
  box_box_proximity(*A, *B, *out);
  const double eps = std::is_same_v<T, float> ? 2e-5 : 1e-9;
  for (int k = 0; k < N; ++k) {
    // The reference uses the rotation as the kernel saw it (rounded to T, then re-orthonormalised
    // by nothing: both see the same, slightly non-orthonormal frame only in float).
    Box a = as[k], b = bs[k];
    a.rotation = a.rotation.cast<T>().template cast<double>();
    b.rotation = b.rotation.cast<T>().template cast<double>();
    ConvexPolytope pa, pb;
    std::vector<Vector3d> ca, cb;
    for (int c = 0; c < 8; ++c) {
      Vector3d p = a.center, q = b.center;
      for (int d = 0; d < 3; ++d) {
        p += ((c >> d & 1) ? 1.0 : -1.0) * a.half_extents[d] * a.rotation.col(d);
        q += ((c >> d & 1) ? 1.0 : -1.0) * b.half_extents[d] * b.rotation.col(d);
      }
      ca.push_back(p), cb.push_back(q);
    }
    ASSERT_EQ(polytope_from_points(ca, pa), Status::Ok);
    ASSERT_EQ(polytope_from_points(cb, pb), Status::Ok);
    Proximity ref;
    ASSERT_EQ(proximity(pa, pb, ref), Status::Ok);
    const std::string what = std::string(to_string(isa)) + " pair " + std::to_string(k);
    if (k >= int(hard.size()) && k % 5 != 0 && k % 16 == 7)
      EXPECT_EQ(out->distance[k], 0.0) << what << " (exact contact)";
    EXPECT_NEAR(out->distance[k], ref.distance, eps * 4) << what;
    EXPECT_NEAR(out->depth[k], ref.penetration_depth, eps * 4) << what;
    if (ref.distance > 1e-3) {
      const Vector3d qa(out->point_a[0][k], out->point_a[1][k], out->point_a[2][k]);
      const Vector3d qb(out->point_b[0][k], out->point_b[1][k], out->point_b[2][k]);
      EXPECT_NEAR((qa - qb).norm(), ref.distance, eps * 8) << what;
      EXPECT_LE(outside(pa, qa), eps * 8) << what;
      EXPECT_LE(outside(pb, qb), eps * 8) << what;
    }
    if (ref.penetration_depth > 1e-3) {
      const Vector3d dir(out->direction[0][k], out->direction[1][k], out->direction[2][k]);
      const Vector3d qa(out->point_a[0][k], out->point_a[1][k], out->point_a[2][k]);
      const Vector3d qb(out->point_b[0][k], out->point_b[1][k], out->point_b[2][k]);
      EXPECT_LE((qa - qb - out->depth[k] * dir).norm(), eps * 16) << what;  // deepest points
      EXPECT_LE(outside(pa, qa), eps * 8) << what;
      EXPECT_LE(outside(pb, qb), eps * 8) << what;
      EXPECT_NEAR(dir.norm(), 1, eps * 4) << what;
      // Moving B by depth * direction must make them just touch (ties between directions, as
      // for centred boxes, may pick either).
      std::vector<Vector3d> moved;
      for (const auto& q : cb) moved.push_back(q + out->depth[k] * dir);
      ConvexPolytope pm;
      ASSERT_EQ(polytope_from_points(moved, pm), Status::Ok);
      Proximity after;
      ASSERT_EQ(proximity(pa, pm, after), Status::Ok);
      EXPECT_NEAR(after.penetration_depth + after.distance, 0, eps * 16) << what;
    }
    if (testing::Test::HasFailure()) return;
  }
}

class BatchedProximity : public testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "NOT TESTED: this CPU lacks " << to_string(GetParam());
  }
  void TearDown() override { force_isa(best_); }
  Isa best_ = active_isa();
};

TEST_P(BatchedProximity, AgreesWithTheExactGeneralPath) {
  check_batched_proximity<double>(GetParam(), 51, 1.5);
  check_batched_proximity<float>(GetParam(), 52, 1.5);
  check_batched_proximity<double>(GetParam(), 53, 4);
}

// A fuzz finding: boxes touching along parallel faces (A's face lies in B's face plane, B's
// edges lie in that plane too), so the facet of A (-) B there is split between several
// generator pairs. Judged pair by pair, rounding called one part's plane separating and
// another's not, and the float distance came out as 320.9 (the distance to the wrong part).
template <class T>
void check_touching_parallel_faces() {
  Box a, b;
  a.center = {-329.296875, -329.296875, 8.03125};
  a.half_extents = {8.03125, 8.03125, 8.03125};
  a.rotation << -0.99881105212901811, 0, -0.04874917583840168, -0.04874917583840168, 1.1102230246251565e-16,
      0.99881105212901822, 0, 0.99999999999999989, 1.1102230246251565e-16;
  b.center = {-329.296875, -329.296875, -329.296875};
  b.half_extents = {329.296875, 329.296875, 329.296875};
  b.rotation << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  auto A = std::make_unique<BoxBatch<T, 16>>(), B = std::make_unique<BoxBatch<T, 16>>();
  auto out = std::make_unique<BoxBoxProximity<T, 16>>();
  for (int k = 0; k < 16; ++k) A->set(k, a), B->set(k, b);
  A->count = B->count = 16;
  box_box_proximity(*A, *B, *out);
  const double tol = (std::is_same_v<T, float> ? 1e-6 : 1e-12) * 1000;  // touching, to rounding
  for (int k = 0; k < 16; ++k) {
    EXPECT_LE(out->distance[k], tol) << "lane " << k;
    EXPECT_LE(out->depth[k], tol) << "lane " << k;
  }
}

TEST_P(BatchedProximity, TouchingAlongParallelFaces) {
  ASSERT_TRUE(force_isa(GetParam()));
  check_touching_parallel_faces<float>();
  check_touching_parallel_faces<double>();
}

INSTANTIATE_TEST_SUITE_P(Isa, BatchedProximity, testing::Values(Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// The single-pair query (separating axis, then the active set on A (-) B) of every ISA against
// the batched kernel (a different algorithm: one facet with an optimality certificate, else all
// 15 facet pairs), on random pairs
// and on near-degenerate ones (aligned, nearly parallel, touching): the active set settles every
// time, so its fallback never runs.
TEST_P(BatchedProximity, SinglePairActiveSetAgreesWithAllFacets) {
  ASSERT_TRUE(force_isa(GetParam()));
  std::mt19937_64 rng(61);
  std::uniform_real_distribution<double> tiny(-1e-9, 1e-9);
  constexpr int N = 1024;
  auto A = std::make_unique<BoxBatch<double, N>>(), B = std::make_unique<BoxBatch<double, N>>();
  auto all = std::make_unique<BoxBoxProximity<double, N>>();
  std::vector<std::pair<Box, Box>> pairs;
  for (int round = 0; round < test::scaled(20, 2); ++round) {
    for (int k = 0; k < N; ++k) {
      Box a = tools::random_box(rng, 1.5), b = tools::random_box(rng, 1.5);
      if (k % 4 == 1) b.rotation = a.rotation;  // parallel faces and edges
      if (k % 4 == 2) b.rotation = a.rotation * tools::axis_angle({1, 2, 3}, tiny(rng));
      if (k % 4 == 3) a.rotation = b.rotation = Eigen::Matrix3d::Identity();
      if (k % 16 == 15) std::tie(a, b) = test::ties::touching_boxes(rng);  // tie-heavy (tests/ties)
      if (k % 16 == 7) a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
      A->set(k, a), B->set(k, b);
      pairs.emplace_back(a, b);
    }
    A->count = B->count = N;
    box_box_proximity(*A, *B, *all);
    for (int k = 0; k < N; ++k) {
      const auto& [a, b] = pairs[round * N + k];
      detail::BoxPair<double> pair;
      detail::PairAnswer<double> got;
      unsigned cold = 0;
      detail::box_pair_proximity(a, b, detail::PairLevel::Witnesses, cold, pair, got);
      ASSERT_TRUE(got.converged) << "pair " << k;
      const double scale = 1e-9 * std::max({1.0, a.center.cwiseAbs().maxCoeff(), b.center.cwiseAbs().maxCoeff()});
      EXPECT_NEAR(got.distance, all->distance[k], scale) << "pair " << k;
      EXPECT_NEAR(got.depth, all->depth[k], scale) << "pair " << k;
      if (k % 16 == 15) {  // exact contact: intersecting, at distance and depth exactly 0, both ways
        EXPECT_TRUE(got.intersecting) << "pair " << k;
        EXPECT_TRUE(got.distance == 0 && all->distance[k] == 0 && got.depth == 0 && all->depth[k] == 0) << "pair " << k;
      }
      // The witnesses realise the answer: p_A - p_B is the closest point of A (-) B, or the
      // deepest boundary point depth * direction.
      const Vector3d pa(got.point_a), pb(got.point_b), dir(got.direction);
      if (got.intersecting)
        EXPECT_LE((pa - pb - got.depth * dir).norm(), scale) << "pair " << k;
      else
        EXPECT_NEAR((pa - pb).norm(), got.distance, scale) << "pair " << k;
      if (testing::Test::HasFailure()) return;
    }
  }
}

}  // namespace
}  // namespace minksum

namespace minksum {
namespace {

// The largest separation of two boxes over the 15 axes, by brute force over their corners (the
// face normals and the edge crosses longer than `tau`): what box_box_separation's bound must
// be. `ambiguous` is set when a cross lies near tau, where the kernel may take it or not.
double sat_gap(const Box& a, const Box& b, double tau, bool& ambiguous) {
  std::vector<Vector3d> axes;
  for (int i = 0; i < 3; ++i) axes.push_back(a.rotation.col(i)), axes.push_back(b.rotation.col(i));
  ambiguous = false;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const Vector3d n = a.rotation.col(i).cross(b.rotation.col(j));
      ambiguous = ambiguous || std::abs(n.norm() - tau) < 0.5 * tau;
      if (n.norm() > tau) axes.push_back(n.normalized());
    }
  double gap = 0;
  for (const Vector3d& n : axes) {
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300};
    for (int q = 0; q < 8; ++q)
      for (int s = 0; s < 2; ++s) {
        const double x = n.dot(box_corner(s ? b : a, q));
        lo[s] = std::min(lo[s], x), hi[s] = std::max(hi[s], x);
      }
    gap = std::max({gap, lo[1] - hi[0], lo[0] - hi[1]});
  }
  return gap;
}

// Whether two polytopes of exact (lattice) coordinates meet, touching included: their surfaces
// meet (exact distance 0), or one holds the other (brute force, far from rounding there).
bool exact_overlap(const ConvexPolytope& a, const ConvexPolytope& b) {
  return test::ties::exact_surface_gap(a, b) == 0 || test::brute_force(a, b).overlap;
}

// A box's 8 corners, from its centre, axes and half extents (the oracles' own, not the library's).
std::vector<Vector3d> corners(const Box& x) {
  std::vector<Vector3d> c;
  for (int q = 0; q < 8; ++q) {
    Vector3d p = x.center;
    for (int d = 0; d < 3; ++d) p += ((q >> d & 1) ? 1.0 : -1.0) * x.half_extents[d] * x.rotation.col(d);
    c.push_back(p);
  }
  return c;
}

// The fused separating-axis kernels against the exact proximity of the general path, and the
// bound against the brute-force separating-axis gap (a constant 0 passes the rest).
template <class T>
void check_fused(Isa isa, unsigned seed) {
  ASSERT_TRUE(force_isa(isa));
  constexpr int N = 1024;
  auto A = std::make_unique<BoxBatch<T, N>>(), B = std::make_unique<BoxBatch<T, N>>();
  auto tri = std::make_unique<TriangleBatch<T, N>>();
  auto sep = std::make_unique<BoxBoxSeparation<T, N>>();
  auto overlap = std::make_unique<BoxTriangleOverlap<T, N>>();
  const auto& hit = overlap->hit;
  std::mt19937_64 rng(seed);
  std::vector<Box> as, bs;
  std::vector<Triangle> ts;
  for (int k = 0; k < N; ++k) {
    Box a = tools::random_box(rng, 1.5), b = tools::random_box(rng, 1.5);
    Triangle t = tools::random_triangle(rng, 1.5);
    // One lane in 16 tie-heavy (tests/ties): lattice boxes and triangles (exact in float too),
    // every other one in exact contact, where touching must count as a hit.
    if (k % 32 == 31) std::tie(a, b) = test::ties::touching_boxes(rng), t = test::ties::lattice_triangle(rng, 2, 1);
    if (k % 32 == 15) std::tie(a, t) = test::ties::touching_box_triangle(rng), b = test::ties::lattice_box(rng, 2, 1);
    for (Box* x : {&a, &b}) {  // what the kernel sees: inputs rounded to T
      x->center = x->center.cast<T>().template cast<double>();
      x->half_extents = x->half_extents.cast<T>().template cast<double>();
      x->rotation = x->rotation.cast<T>().template cast<double>();
    }
    t = {t.a.cast<T>().template cast<double>(), t.b.cast<T>().template cast<double>(),
         t.c.cast<T>().template cast<double>()};
    as.push_back(a), bs.push_back(b), ts.push_back(t);
    A->set(k, a), B->set(k, b), tri->set(k, t);
  }
  A->count = B->count = tri->count = N;
  box_box_separation(*A, *B, *sep);
  box_triangle_overlap(*A, *tri, *overlap);
  const double tol = std::is_same_v<T, float> ? 1e-4 : 1e-9;
  int both[2] = {0, 0}, separated_bounds = 0, tie_lanes = 0, checked = 0;
  // Every lane checked at full size; under the sanitizers (MINKSUM_TEST_SCALE) the tie lanes
  // and a sample of the others: the kernels ran on all of them, and the checks' own polytopes
  // and exact queries were four fifths of the sanitized suite's time here.
  const int stride = N / test::scaled(N, 64), tie_stride = 8 / test::scaled(8);
  for (int k = 0; k < N; ++k) {
    if (k % stride != 0 && !(k % 16 == 15 && (k / 16) % tie_stride == 0)) continue;
    ++checked;
    ConvexPolytope pa, pb, pt;
    ASSERT_EQ(polytope_from_points(corners(as[k]), pa), Status::Ok);
    ASSERT_EQ(polytope_from_points(corners(bs[k]), pb), Status::Ok);
    ASSERT_EQ(polytope_from_triangle(ts[k], pt), Status::Ok);
    Proximity ab, at;
    ASSERT_EQ(proximity(pa, pb, ab), Status::Ok);
    ASSERT_EQ(proximity(pa, pt, at), Status::Ok);
    const std::string what = std::string(to_string(isa)) + " pair " + std::to_string(k);
    if (k % 16 == 15 && (k / 16) % tie_stride == 0) {  // exactly: the exact surface gap's verdict (and containment)
      EXPECT_EQ(sep->hit[k] != 0, exact_overlap(pa, pb)) << what;
      EXPECT_EQ(hit[k] != 0, exact_overlap(pa, pt)) << what;
      tie_lanes += 2;
    }
    if (ab.distance > tol || ab.penetration_depth > tol) EXPECT_EQ(sep->hit[k] != 0, ab.intersecting) << what;
    EXPECT_LE(sep->bound[k], ab.distance + tol) << what;  // a lower bound
    if (sep->hit[k]) EXPECT_EQ(sep->bound[k], 0) << what;
    bool ambiguous;
    const double gap = sat_gap(as[k], bs[k], kParallelThreshold<T>, ambiguous);
    if (!ambiguous) EXPECT_NEAR(sep->bound[k], gap, tol) << what;
    separated_bounds += gap > tol;
    if (at.distance > tol || at.penetration_depth > tol) EXPECT_EQ(hit[k] != 0, at.intersecting) << what;
    ++both[ab.intersecting];
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(both[0], checked / 10);
  EXPECT_GT(both[1], checked / 10);
  EXPECT_GT(separated_bounds, checked / 10);
  EXPECT_EQ(tie_lanes, N / 8 / tie_stride);
}

class FusedSat : public testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "NOT TESTED: this CPU lacks " << to_string(GetParam());
  }
  void TearDown() override { force_isa(best_); }
  Isa best_ = active_isa();
};

TEST_P(FusedSat, AgreesWithTheExactProximity) {
  check_fused<double>(GetParam(), 61);
  check_fused<float>(GetParam(), 62);
}

INSTANTIATE_TEST_SUITE_P(Isa, FusedSat, testing::Values(Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512),
                         [](const auto& info) { return std::string(to_string(info.param)); });

}  // namespace
}  // namespace minksum
