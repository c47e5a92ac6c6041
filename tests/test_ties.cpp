// Exact contact on every query kind (tests/ties: lattice boxes face on face, a triangle's corner
// on a box's face or lying in its plane, triangles sharing a corner, an edge point or a face
// point): the verdict is intersecting and the distance exactly 0, for the single queries, the
// polytopes and the posed shapes (cold and coherent), and the batched kernels.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include "checks.hpp"
#include "ties.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

// A common exact motion of both operands: a quarter turn and a lattice translation.
Eigen::Isometry3d lattice_motion(std::mt19937_64& rng) {
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  m.linear() = test::ties::quarter_turn(rng);
  m.translation() = test::ties::lattice_point(rng, 8, 3);
  return m;
}

// The contact verdict of one answer: Ok, intersecting, distance exactly 0.
void expect_contact(Status s, const Proximity& p, const std::string& what) {
  ASSERT_EQ(s, Status::Ok) << what;
  EXPECT_TRUE(p.intersecting) << what;
  EXPECT_EQ(p.distance, 0.0) << what;
}

// The same pair as polytopes, as shapes under one exact motion (cold and through a cache).
void expect_contact_as_shapes(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, std::mt19937_64& rng,
                              ProximityCache& cache, const std::string& what) {
  ConvexPolytope A, B;
  ConvexShape SA, SB;
  Proximity p;
  if (polytope_from_points(a, A) == Status::Ok && polytope_from_points(b, B) == Status::Ok)
    expect_contact(proximity(A, B, p), p, what + " as polytopes");
  if (shape_from_points(a, SA) != Status::Ok || shape_from_points(b, SB) != Status::Ok) return;  // (a flat triangle)
  const Eigen::Isometry3d m = lattice_motion(rng);
  expect_contact(proximity(SA, m, SB, m, p, kWantContact), p, what + " as shapes");
  expect_contact(proximity(SA, m, SB, m, cache, p, kWantContact), p, what + " as shapes, coherent");
}

TEST(Ties, ExactContactIsIntersectingAtDistanceZero) {
  std::mt19937_64 rng(2026);
  const int n = test::scaled(400);
  ProximityCache boxes, box_tri, shapes;
  auto A = std::make_unique<BoxBatch<double, 16>>(), B = std::make_unique<BoxBatch<double, 16>>();
  auto S = std::make_unique<TriangleBatch<double, 16>>(), T = std::make_unique<TriangleBatch<double, 16>>();
  auto prox = std::make_unique<BoxBoxProximity<double, 16>>();
  auto dist = std::make_unique<TriangleDistances<double, 16>>();
  for (int k = 0; k < n; ++k) {
    const std::string at = " case " + std::to_string(k);
    const auto [a, b] = test::ties::touching_boxes(rng);
    const auto [box, tri] = test::ties::touching_box_triangle(rng);
    const auto [s, t] = test::ties::touching_triangles(rng);
    Proximity p;
    expect_contact(proximity(a, b, p), p, "box-box" + at);
    expect_contact(proximity(a, b, boxes, p), p, "box-box coherent" + at);
    expect_contact(proximity(box, tri, p), p, "box-triangle" + at);
    expect_contact(proximity(box, tri, box_tri, p), p, "box-triangle coherent" + at);
    expect_contact(proximity(s, t, p), p, "triangle-triangle" + at);
    expect_contact_as_shapes(test::ties::corners(a), test::ties::corners(b), rng, shapes, "box-box" + at);
    expect_contact_as_shapes(test::ties::corners(box), test::ties::corners(tri), rng, shapes, "box-triangle" + at);
    // The batched kernels, 16 lanes at a time.
    const int lane = k % 16;
    A->set(lane, a), B->set(lane, b), S->set(lane, s), T->set(lane, t);
    if (lane == 15) {
      A->count = B->count = S->count = T->count = 16;
      box_box_proximity(*A, *B, *prox);
      triangle_distance(*S, *T, *dist);
      for (int j = 0; j < 16; ++j) {
        EXPECT_EQ(prox->distance[j], 0.0) << "box_box_proximity lane " << j << at;
        EXPECT_EQ(dist->distance[j], 0.0) << "batched triangle_distance lane " << j << at;
      }
    }
    if (testing::Test::HasFailure()) return;
  }
}

}  // namespace
}  // namespace minksum
