// Determinism: the same input gives bit-identical output from call to call on one ISA (no
// uninitialised scratch, no order-dependent state), for the kernels, the sums, the queries
// and the mesh distance. Across ISAs the kernels differ only within the bounds their own
// tests check against the scalar reference (test_kernels.cpp, test_query.cpp).
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cstring>
#include <memory>
#include <random>
#include <tuple>

#include "checks.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

template <class T>
bool same_bytes(const T& x, const T& y) {
  return std::memcmp(&x, &y, sizeof(T)) == 0;
}
// Field by field where a struct has padding (its bytes are not part of the value).
bool same(const Proximity& x, const Proximity& y) {
  return x.intersecting == y.intersecting && same_bytes(x.distance, y.distance) && same_bytes(x.point_a, y.point_a) &&
         same_bytes(x.point_b, y.point_b) && same_bytes(x.max_distance, y.max_distance) &&
         same_bytes(x.far_a, y.far_a) && same_bytes(x.far_b, y.far_b) &&
         same_bytes(x.penetration_depth, y.penetration_depth) &&
         same_bytes(x.penetration_direction, y.penetration_direction);
}
bool same(const MeshDistance& x, const MeshDistance& y) {
  return same_bytes(x.distance, y.distance) && same_bytes(x.point_a, y.point_a) && same_bytes(x.point_b, y.point_b) &&
         x.triangle_a == y.triangle_a && x.triangle_b == y.triangle_b && x.intersecting == y.intersecting &&
         x.stats.node_pairs == y.stats.node_pairs && x.stats.triangle_pairs == y.stats.triangle_pairs &&
         x.stats.candidates_a == y.stats.candidates_a && x.stats.candidates_b == y.stats.candidates_b;
}

class Determinism : public testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "NOT TESTED: this CPU lacks " << to_string(GetParam());
    force_isa(GetParam());
  }
  void TearDown() override { force_isa(best_); }
  Isa best_ = active_isa();
};

TEST_P(Determinism, KernelsRepeatBitForBit) {
  std::mt19937_64 rng(5);
  auto A = std::make_unique<BoxBatch<float, 256>>(), B = std::make_unique<BoxBatch<float, 256>>();
  auto T = std::make_unique<TriangleBatch<float, 256>>();
  for (int k = 0; k < 256; ++k) {
    Box a = tools::random_box(rng, 2), b = tools::random_box(rng, 2);
    Triangle t = tools::random_triangle(rng, 2);
    // Ties, where an order-dependent choice would show (tests/ties): lattice lanes, and lanes in
    // exact contact.
    if (k % 8 == 3)
      a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1),
      t = test::ties::lattice_triangle(rng, 2, 1);
    if (k % 16 == 7) std::tie(a, b) = test::ties::touching_boxes(rng);
    if (k % 16 == 15) std::tie(a, t) = test::ties::touching_box_triangle(rng);
    A->set(k, a), B->set(k, b), T->set(k, t);
  }
  A->count = B->count = T->count = 256;
  auto p1 = std::make_unique<BoxBoxPlanes<float, 256>>(), p2 = std::make_unique<BoxBoxPlanes<float, 256>>();
  auto q1 = std::make_unique<BoxBoxProximity<float, 256>>(), q2 = std::make_unique<BoxBoxProximity<float, 256>>();
  auto t1 = std::make_unique<BoxTrianglePlanes<float, 256>>(), t2 = std::make_unique<BoxTrianglePlanes<float, 256>>();
  // Different garbage in the output buffers first: nothing of it may survive.
  std::memset(p1.get(), 0x11, sizeof *p1), std::memset(p2.get(), 0x7f, sizeof *p2);
  std::memset(q1.get(), 0x11, sizeof *q1), std::memset(q2.get(), 0x7f, sizeof *q2);
  std::memset(t1.get(), 0x11, sizeof *t1), std::memset(t2.get(), 0x7f, sizeof *t2);
  box_box_planes(*A, *B, true, *p1), box_box_planes(*A, *B, true, *p2);
  box_box_proximity(*A, *B, *q1), box_box_proximity(*A, *B, *q2);
  box_triangle_planes(*A, *T, false, *t1), box_triangle_planes(*A, *T, false, *t2);
  // Compare the lanes in use (padding lanes past kRow may hold anything).
  for (int k = 0; k < 256; ++k) {
    for (int p = 0; p < 30; ++p) ASSERT_EQ(p1->offset[p][k], p2->offset[p][k]) << k;
    for (int p = 0; p < 15; ++p) ASSERT_EQ(p1->code[p][k], p2->code[p][k]) << k;
    ASSERT_EQ(q1->distance[k], q2->distance[k]) << k;
    ASSERT_EQ(q1->depth[k], q2->depth[k]) << k;
    for (int d = 0; d < 3; ++d) ASSERT_EQ(q1->point_a[d][k], q2->point_a[d][k]) << k;
    for (int p = 0; p < 26; ++p) ASSERT_EQ(t1->offset[p][k], t2->offset[p][k]) << k;
  }
}

TEST_P(Determinism, QueriesRepeatBitForBit) {
  std::mt19937_64 rng(6);
  for (int k = 0; k < 2000; ++k) {
    Box a = tools::random_box(rng, 1.5), b = tools::random_box(rng, 1.5);
    if (k % 8 == 3) a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);  // ties
    if (k % 8 == 7) std::tie(a, b) = test::ties::touching_boxes(rng);
    Proximity x, y;
    ASSERT_EQ(proximity(a, b, x), Status::Ok);
    ASSERT_EQ(proximity(a, b, y), Status::Ok);
    ASSERT_TRUE(same(x, y)) << "pair " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Isa, Determinism, testing::Values(Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(Determinism, SumsRepeatBitForBit) {
  auto pairs = tools::table1_pairs();
  std::mt19937_64 rng(9);
  for (int k = 0; k < 8; ++k)  // ties (tests/ties): lattice solids, coplanar faces and parallel edges
    pairs.push_back({"lattice " + std::to_string(k), test::ties::lattice_solid_points(rng, 2, 1),
                     test::ties::lattice_solid_points(rng, 2, 1)});
  for (const auto& pair : pairs) {
    ConvexPolytope A, B;
    ASSERT_EQ(polytope_from_points(pair.a, A), Status::Ok);
    ASSERT_EQ(polytope_from_points(pair.b, B), Status::Ok);
    for (Method method : {Method::Fast, Method::Reference, Method::Hull}) {
      MinkowskiSum x, y;
      ASSERT_EQ(minkowski_sum(A, B, x, method), Status::Ok);
      ASSERT_EQ(minkowski_sum(A, B, y, method), Status::Ok);
      ASSERT_EQ(x.F, y.F) << pair.name;
      for (int f = 0; f < x.F; ++f) {
        ASSERT_TRUE(same_bytes(x.planes[f], y.planes[f])) << pair.name << " plane " << f;
        ASSERT_TRUE(std::equal(x.facet(f).begin(), x.facet(f).end(), y.facet(f).begin(), y.facet(f).end()))
            << pair.name;
      }
    }
  }
}

TEST(Determinism, MeshDistanceRepeatsBitForBit) {
  const auto m = test::mesh_setup("bun_zipper_res4.ply", 16);
  const Octree& A = m->tree;
  MeshWorkspace& ws = m->ws;
  std::mt19937_64 rng(7);
  for (int k = 0; k < 50; ++k) {
    Eigen::Isometry3d pose = test::random_pose(rng, 0.2);
    if (k % 5 == 4) {  // a tie: the copy half-turned about the z axis through a corner (exact contact)
      const Vector3d v = m->mesh.vertices[rng() % m->mesh.vertices.size()];
      pose.linear() = Vector3d(-1, -1, 1).asDiagonal(), pose.translation() = Vector3d(2 * v.x(), 2 * v.y(), 0);
    }
    MeshDistance x, y;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, x), Status::Ok);
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, y), Status::Ok);  // the workspace is reused
    ASSERT_TRUE(same(x, y)) << "pose " << k;
  }
}

}  // namespace
}  // namespace minksum
