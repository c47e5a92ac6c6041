// Queries face to face (tools::face_pairs: boxes, prisms, a box on a prism, a polytope's flat
// face on a box, an edge along a face), apart by 1e-1 ... 1e-12 of the size, exactly touching
// and pressed, sliding with and without rocking: brute force on the explicitly transformed
// polytopes (test::brute_force) is the oracle; the exhaustive search is never needed; the
// coherent query equals the cold one; the witnesses slide without jumps.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include "checks.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

const Isometry3d kPoseA(Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));

void build(const tools::FacePair& p, ConvexShape& A, ConvexShape& B) {
  ASSERT_EQ(p.a_is_box ? shape_from_box(p.box_a, A) : shape_from_points(p.a, A), Status::Ok);
  ASSERT_EQ(p.b_is_box ? shape_from_box(p.box_b, B) : shape_from_points(p.b, B), Status::Ok);
}

// Largest distance of x outside the polytope's face planes (0 inside).
double outside(const ConvexPolytope& P, const Vector3d& x) {
  double worst = 0;
  for (const auto& f : P.faces) worst = std::max(worst, f.normal.dot(x) - f.offset);
  return worst;
}

constexpr double kGaps[] = {1e-1, 1e-3, 1e-6, 1e-9, 1e-12, 0, -1e-12, -1e-6, -1e-3};

TEST(FaceToFace, EveryFamilyEqualsBruteForceWithoutTheSearch) {
  // Every 3rd of 64 ticks (at a reduced MINKSUM_TEST_SCALE, the sanitizer run: every 30th).
  const int stride = 30 / std::min(10, test::scaled(10));
  int checked = 0;
  for (const auto& pair : tools::face_pairs()) {
    ConvexShape A, B;
    build(pair, A, B);
    const ConvexPolytope TA = test::transformed(A.polytope(), kPoseA);
    for (bool rocking : {false, true})
      for (double gap : kGaps) {
        ProximityCache cache, plain_cache;
        int ticks = 0;
        for (int k = 0; k < 64; k += stride) {
          const std::string where =
              pair.name + (rocking ? " rocking" : "") + " gap " + std::to_string(gap) + " tick " + std::to_string(k);
          const Isometry3d pose_b = kPoseA * tools::face_pose(pair, k, 64, gap, rocking);
          Proximity cold, warm;
          ASSERT_EQ(proximity(A, kPoseA, B, pose_b, cold, Want::Patch), Status::Ok);
          ASSERT_EQ(proximity(A, kPoseA, B, pose_b, cache, warm, Want::Patch), Status::Ok);
          const ConvexPolytope TB = test::transformed(B.polytope(), pose_b);
          const test::Oracle o = test::brute_force(TA, TB);
          const double tol = 1e-12 * 2;  // of the size (about 2)
          // The oracle's answer, with witnesses on the shapes that realise it.
          const auto matches_oracle = [&](const Proximity& p) {
            EXPECT_FALSE(p.searched) << where;
            EXPECT_EQ(p.intersecting, gap <= 0) << where;
            EXPECT_NEAR(p.distance, o.distance, tol) << where;
            EXPECT_NEAR(p.penetration_depth, o.depth, tol) << where;
            EXPECT_LE(outside(TA, p.point_a), tol) << where;
            EXPECT_LE(outside(TB, p.point_b), tol) << where;
            if (p.intersecting)
              EXPECT_LE((p.point_a - p.point_b - p.penetration_depth * p.penetration_direction).norm(), tol) << where;
            else
              EXPECT_NEAR((p.point_a - p.point_b).norm(), p.distance, tol) << where;
          };
          matches_oracle(cold);
          // The coherent query: the same answer.
          EXPECT_FALSE(warm.searched) << where;
          EXPECT_EQ(warm.intersecting, cold.intersecting) << where;
          EXPECT_NEAR(warm.distance, cold.distance, tol) << where;
          EXPECT_NEAR(warm.penetration_depth, cold.penetration_depth, tol) << where;
          EXPECT_LE((warm.point_a - cold.point_a).norm(), 1e-9) << where;
          EXPECT_LE((warm.point_b - cold.point_b).norm(), 1e-9) << where;
          // At the default level (GJK's witnesses, the face probe's vertex over the face): the
          // same oracle, cold and coherent.
          Proximity plain[2];
          ASSERT_EQ(proximity(A, kPoseA, B, pose_b, plain[0]), Status::Ok);
          ASSERT_EQ(proximity(A, kPoseA, B, pose_b, plain_cache, plain[1]), Status::Ok);
          for (const Proximity& p : plain) matches_oracle(p);
          ++checked;
          ++ticks;
        }
        EXPECT_EQ(cache.searched, 0) << pair.name;
        // Clear answers stay warm after the first tick (two boxes: apart; overlapping, the box
        // kernel's separating axis test answers cold). Near contact the cold query answers.
        const bool boxes = pair.a_is_box && pair.b_is_box;
        if (std::abs(gap) >= 1e-6 && (!boxes || gap > 0))
          EXPECT_EQ(cache.warm, ticks - 1) << pair.name << " gap " << gap;
      }
  }
  EXPECT_GE(checked, 8 * 2 * 9 * 3);  // the eight families, flat and rocking, nine gaps, 3+ ticks
}

// Sliding flat (no rocking), the witnesses move with B: no jump larger than B's own step.
TEST(FaceToFace, WitnessesSlideWithoutJumps) {
  for (const auto& pair : tools::face_pairs())
    for (double gap : {1e-3, 0.0, -1e-3}) {
      ConvexShape A, B;
      build(pair, A, B);
      Proximity last;
      Isometry3d last_pose;
      for (int k = 0; k < 400; ++k) {
        const Isometry3d pose_b = kPoseA * tools::face_pose(pair, k, 1024, gap, false);
        Proximity p;
        ASSERT_EQ(proximity(A, kPoseA, B, pose_b, p, Want::Patch), Status::Ok);
        if (k > 0) {
          const double step = (pose_b.translation() - last_pose.translation()).norm();
          const std::string where = pair.name + " gap " + std::to_string(gap) + " tick " + std::to_string(k);
          EXPECT_LE((p.point_a - last.point_a).norm(), step * (1 + 1e-6) + 1e-12) << where;
          EXPECT_LE((p.point_b - last.point_b).norm(), step * (1 + 1e-6) + 1e-12) << where;
        }
        last = p, last_pose = pose_b;
      }
    }
}

// Shapes built from boxes and triangles answer through the box-box, box-triangle and
// triangle-triangle paths: the same answer as those overloads on the placed boxes and
// triangles (B before A: witnesses exchanged, direction negated), and as brute force.
TEST(FaceToFace, BoxAndTriangleShapesTakeTheirOwnPaths) {
  std::mt19937_64 rng(17);
  for (int k = 0; k < 300; ++k) {
    const Box a = tools::random_box(rng, 1.0), b = tools::random_box(rng, 1.0);
    const Triangle t = tools::random_triangle(rng, 1.0);
    ConvexShape A, B, T;
    ASSERT_EQ(shape_from_box(a, A), Status::Ok);
    ASSERT_EQ(shape_from_box(b, B), Status::Ok);
    ASSERT_EQ(shape_from_triangle(t, T), Status::Ok);
    const Isometry3d pa(Eigen::Translation3d(0.1 * k, 0, 0) *
                        Eigen::AngleAxisd(0.01 * k, Vector3d(0, 1, 1).normalized()));
    const Isometry3d pb(Eigen::AngleAxisd(0.02 * k, Vector3d(1, 0, 1).normalized()));
    const auto place = [](const Box& x, const Isometry3d& pose) {
      Box y = x;
      y.center = pose * x.center, y.rotation = pose.linear() * x.rotation;
      return y;
    };
    const Triangle tb{pb * t.a, pb * t.b, pb * t.c};
    Proximity shapes, boxes, bt, tbx, direct;
    ASSERT_EQ(proximity(A, pa, B, pb, shapes), Status::Ok);
    ASSERT_EQ(proximity(place(a, pa), place(b, pb), boxes), Status::Ok);
    EXPECT_EQ(shapes.distance, boxes.distance);
    EXPECT_EQ(shapes.penetration_depth, boxes.penetration_depth);
    EXPECT_EQ(shapes.point_a, boxes.point_a);
    ASSERT_EQ(proximity(T, pb, A, pa, tbx), Status::Ok);
    ASSERT_EQ(proximity(place(a, pa), tb, direct), Status::Ok);
    EXPECT_EQ(tbx.point_a, direct.point_b);
    EXPECT_EQ(tbx.point_b, direct.point_a);
    EXPECT_EQ(tbx.penetration_direction, -direct.penetration_direction);
    EXPECT_EQ(tbx.distance, direct.distance);
    // And brute force on the placed polytopes.
    const test::Oracle o = test::brute_force(test::transformed(T.polytope(), pb), test::transformed(A.polytope(), pa));
    EXPECT_NEAR(tbx.distance, o.distance, 1e-9 * (1 + 0.1 * k));
    EXPECT_NEAR(tbx.penetration_depth, o.depth, 1e-9 * (1 + 0.1 * k));
    EXPECT_FALSE(tbx.searched);
    ProximityCache cache;
    ASSERT_EQ(proximity(T, pb, A, pa, cache, bt), Status::Ok);
    EXPECT_EQ(bt.intersecting, direct.intersecting);
    EXPECT_NEAR(bt.distance, direct.distance, 1e-12 * (1 + 0.1 * k));
  }
}

}  // namespace
}  // namespace minksum
