// Coherence (ProximityCache): along smooth trajectories and under adversarial motion, every
// query that starts from the last answer gives the cold query's answer, on every ISA.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cmath>
#include <random>

#include "checks.hpp"
#include "ties.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// The coherent answer equals the cold one: the verdict, the distance or depth to 1e-12 of the
// pair's size, the direction, and witness points that realise it. Where the nearest points are
// unique (always, for generic poses: `unique`), the same points; the farthest pair where `want`
// asked for it. Given the corners of A and B (tie-heavy poses, where several directions may
// share the least depth), the direction need not be the cold one, but must realise the depth:
// moving B by depth * direction just separates them.
void expect_same(const Proximity& cold, const Proximity& warm, double size, bool unique, const std::string& where,
                 Want want = Want::All, const std::vector<Vector3d>& corners_a = {},
                 const std::vector<Vector3d>& corners_b = {}) {
  const double tol = 1e-12 * size;
  ASSERT_EQ(warm.intersecting, cold.intersecting) << where;
  EXPECT_NEAR(warm.distance, cold.distance, tol) << where;
  EXPECT_NEAR(warm.penetration_depth, cold.penetration_depth, tol) << where;
  if (!cold.intersecting) {
    EXPECT_NEAR((warm.point_a - warm.point_b).norm(), warm.distance, tol) << where;
  } else if (cold.penetration_depth > 1e-9 * size && !corners_a.empty()) {
    const Vector3d& u = warm.penetration_direction;
    double push = -1e300;  // h_A(u) + h_B(-u)
    for (const Vector3d& a : corners_a)
      for (const Vector3d& b : corners_b) push = std::max(push, (a - b).dot(u));
    EXPECT_NEAR(push, cold.penetration_depth, tol) << where << ": the direction does not realise the depth";
  } else if (cold.penetration_depth > 1e-9 * size) {
    EXPECT_LE((warm.penetration_direction - cold.penetration_direction).norm(), 1e-6) << where;
  }
  if (unique) {
    EXPECT_LE((warm.point_a - cold.point_a).norm(), 1e-7 * size) << where;
    EXPECT_LE((warm.point_b - cold.point_b).norm(), 1e-7 * size) << where;
  }
  if (has(want, Want::MaxDistance)) {  // (else both hold the default, which proves nothing)
    EXPECT_GT(cold.max_distance, 0) << where;
    EXPECT_NEAR(warm.max_distance, cold.max_distance, tol) << where;
  }
}

Box placed(const Box& body, const Isometry3d& pose) {
  Box b = body;
  b.center = pose * body.center, b.rotation = pose.linear() * body.rotation;
  return b;
}

// One tick of a tie-heavy walk (tests/ties): a step of 1/8 along an axis (back towards the
// origin when it strays past `reach`), and every 40th tick a quarter turn. Lattice shapes under
// such poses keep exact coordinates, and pass through exact face, edge and corner contact.
void lattice_step(std::mt19937_64& rng, int tick, double reach, Isometry3d& pose) {
  const int axis = int(rng() % 3);
  const double at = pose.translation()[axis];
  pose.translation()[axis] += (std::abs(at) > reach ? -at / std::abs(at) : rng() % 2 ? 1.0 : -1.0) / 8;
  if (tick % 40 == 0) pose.linear() = test::ties::quarter_turn(rng);
}

class Coherence : public testing::TestWithParam<Isa> {
 protected:
  void SetUp() override {
    if (!isa_supported(GetParam())) GTEST_SKIP() << "this CPU lacks " << to_string(GetParam());
    saved_ = active_isa();
    force_isa(GetParam());
  }
  void TearDown() override {
    if (isa_supported(GetParam())) force_isa(saved_);
  }
  void lattice_walks();
  Isa saved_ = Isa::Scalar;
};

// Box pairs along five seeded trajectories that pass in and out of contact: the cache
// answers most ticks (or this test would prove nothing), and every answer is the cold one.
TEST_P(Coherence, BoxPairsAlongTrajectories) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> h(0.2, 1);
  long warm = 0, ticks = 0, contacts = 0;
  for (unsigned seed = 1; seed <= 5; ++seed) {
    Box a, body;
    a.half_extents = Vector3d(h(rng), h(rng), h(rng)), body.half_extents = Vector3d(h(rng), h(rng), h(rng));
    a.rotation = tools::axis_angle(Vector3d(1, 2, 3), 0.3 * seed);
    const double size = a.half_extents.norm() + body.half_extents.norm();
    const auto path = tools::trajectory(seed, 3000, 0.6 * size, 1.6 * size, 0.01 * size);
    ProximityCache cache;
    for (size_t k = 0; k < path.size(); ++k) {
      const Box b = placed(body, path[k]);
      Proximity cold, hot;
      ASSERT_EQ(proximity(a, b, cold, Want::All), Status::Ok);
      ASSERT_EQ(proximity(a, b, cache, hot, Want::All), Status::Ok);
      expect_same(cold, hot, size, true, "seed " + std::to_string(seed) + " tick " + std::to_string(k));
      if (testing::Test::HasFailure()) return;
      contacts += cold.intersecting;
    }
    warm += cache.warm, ticks += long(path.size());
    EXPECT_EQ(cache.warm + cache.cold, long(path.size()));
  }
  EXPECT_GT(contacts, ticks / 10);          // the paths do pass through contact
  EXPECT_GT(warm, (ticks - contacts) / 2);  // and the cache answers most separated ticks
  // A tie-heavy walk (tests/ties): lattice boxes, B stepping 1/8 along an axis each tick (back
  // towards the origin past 3) and taking a quarter turn now and then, through exact face, edge
  // and corner contact, where the verdict must be the cold one exactly.
  const Box la = test::ties::lattice_box(rng, 1, 1), lbody = test::ties::lattice_box(rng, 1, 1);
  Isometry3d pose = Isometry3d::Identity();
  ProximityCache cache;
  int touching = 0;
  for (int k = 0; k < 3000; ++k) {
    lattice_step(rng, k, 3, pose);
    const Box lb = placed(lbody, pose);
    Proximity cold, hot;
    ASSERT_EQ(proximity(la, lb, cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(la, lb, cache, hot, Want::All), Status::Ok);
    expect_same(cold, hot, 8, false, "lattice walk tick " + std::to_string(k), Want::All, test::ties::corners(la),
                test::ties::corners(lb));
    if (testing::Test::HasFailure()) return;
    if (cold.intersecting && cold.penetration_depth == 0) {
      EXPECT_EQ(hot.distance, 0.0) << "lattice walk tick " << k;
      ++touching;
    }
  }
  EXPECT_GT(touching, 0);  // the walk did pass through exact contact
}

// Prepared shapes (Table 1 pairs, hulls of 64 and 256 sphere points) and box-triangle pairs
// along trajectories.
TEST_P(Coherence, ShapesAlongTrajectories) {
  std::vector<std::pair<std::vector<Vector3d>, std::vector<Vector3d>>> pairs;
  for (const auto& t : tools::table1_pairs()) pairs.emplace_back(t.a, t.b);
  pairs.emplace_back(tools::sphere_points(64, 1), tools::sphere_points(64, 2));
  pairs.emplace_back(tools::sphere_points(256, 3), tools::sphere_points(256, 4));
  long warm = 0, ticks = 0;
  for (size_t i = 0; i < pairs.size(); ++i) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(pairs[i].first, A), Status::Ok);
    ASSERT_EQ(shape_from_points(pairs[i].second, B), Status::Ok);
    const Isometry3d pose_a(Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.4, Vector3d::UnitY()));
    const auto path = tools::trajectory(unsigned(10 + i), 1500, 1.0, 3.5, 0.02);
    ProximityCache cache;
    for (size_t k = 0; k < path.size(); ++k) {
      const Isometry3d pose_b = pose_a * path[k];
      Proximity cold, hot;
      ASSERT_EQ(proximity(A, pose_a, B, pose_b, cold, Want::Patch), Status::Ok);
      ASSERT_EQ(proximity(A, pose_a, B, pose_b, cache, hot, Want::Patch), Status::Ok);
      expect_same(cold, hot, 4, false, "pair " + std::to_string(i) + " tick " + std::to_string(k), Want::Patch);
      if (testing::Test::HasFailure()) return;
    }
    warm += cache.warm, ticks += long(path.size());
  }
  EXPECT_GT(warm, ticks * 3 / 4);
  // A box and a triangle, the triangle carried along the trajectory.
  Box box;
  box.half_extents = Vector3d(0.5, 0.3, 0.8);
  const Triangle body{Vector3d(0, 0, 0), Vector3d(1.2, 0.1, 0), Vector3d(0.3, 0.9, 0.2)};
  ProximityCache cache;
  const auto path = tools::trajectory(31, 2000, 0.3, 2.0, 0.015);
  for (size_t k = 0; k < path.size(); ++k) {
    const Triangle t{path[k] * body.a, path[k] * body.b, path[k] * body.c};
    Proximity cold, hot;
    ASSERT_EQ(proximity(box, t, cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(box, t, cache, hot, Want::All), Status::Ok);
    expect_same(cold, hot, 2, false, "box-triangle tick " + std::to_string(k));
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(cache.warm, long(path.size()) / 2);
  lattice_walks();
}

// Tie-heavy walks (tests/ties; a quarter of the ticks under the sanitizer): lattice shapes of 4
// to 12 points, and a lattice box and triangle, B stepping by lattice_step through exact
// contact. The coherent verdict is the cold one exactly, the distance at contact exactly 0; and
// every 25th tick the shapes' verdict and distance equal the exact ones (the exact surface gap,
// and containment where it is 0).
void Coherence::lattice_walks() {
  std::mt19937_64 rng(41);
  int touching = 0;
  for (int walk = 0; walk < 3; ++walk) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(test::ties::lattice_solid_points(rng, 2, 1), A), Status::Ok);
    ASSERT_EQ(shape_from_points(test::ties::lattice_solid_points(rng, 2, 1), B), Status::Ok);
    Isometry3d pose_a = Isometry3d::Identity(), pose_b = Isometry3d::Identity();
    pose_a.linear() = test::ties::quarter_turn(rng);
    ProximityCache cache;
    for (int k = 0; k < test::scaled(1000, 250); ++k) {
      const std::string where = "lattice walk " + std::to_string(walk) + " tick " + std::to_string(k);
      lattice_step(rng, k, 4, pose_b);
      Proximity cold, hot;
      ASSERT_EQ(proximity(A, pose_a, B, pose_b, cold, Want::Patch), Status::Ok);
      ASSERT_EQ(proximity(A, pose_a, B, pose_b, cache, hot, Want::Patch), Status::Ok);
      const ConvexPolytope TA = test::transformed(A.polytope(), pose_a), TB = test::transformed(B.polytope(), pose_b);
      expect_same(cold, hot, 8, false, where, Want::Patch, TA.vertices, TB.vertices);
      if (cold.intersecting && cold.penetration_depth == 0) {
        EXPECT_EQ(hot.distance, 0.0) << where;
        ++touching;
      }
      if (k % 25 == 0) {
        const double gap = test::ties::exact_surface_gap(TA, TB);
        ASSERT_EQ(hot.intersecting, gap == 0 || test::brute_force(TA, TB).overlap) << where << ": exact gap " << gap;
        if (!hot.intersecting) EXPECT_NEAR(hot.distance, gap, 1e-12) << where;
      }
      if (testing::Test::HasFailure()) return;
    }
  }
  const Box box = test::ties::lattice_box(rng, 1, 1);
  const Triangle body = test::ties::lattice_triangle(rng, 1, 1);
  Isometry3d pose = Isometry3d::Identity();
  ProximityCache cache;
  for (int k = 0; k < test::scaled(3000, 750); ++k) {
    lattice_step(rng, k, 3, pose);
    const Triangle t{pose * body.a, pose * body.b, pose * body.c};
    Proximity cold, hot;
    ASSERT_EQ(proximity(box, t, cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(box, t, cache, hot, Want::All), Status::Ok);
    expect_same(cold, hot, 8, false, "lattice box-triangle tick " + std::to_string(k), Want::All,
                test::ties::corners(box), test::ties::corners(t));
    if (cold.intersecting && cold.penetration_depth == 0) {
      EXPECT_EQ(hot.distance, 0.0) << "lattice box-triangle tick " << k;
      ++touching;
    }
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(touching, 0);  // the walks did pass through exact contact
}

INSTANTIATE_TEST_SUITE_P(Isa, Coherence, testing::Values(Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512),
                         [](const auto& info) { return std::string(to_string(info.param)); });

// Motion no cache foresees: teleports, 180-degree flips, jumps into deep penetration and out,
// exactly touching poses, and caches filled by another pair, another kind of query, or with
// indices that fit nothing. Every answer is still the cold one.
TEST(CoherenceAdversarial, BoxesAndShapes) {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> u(-1, 1);
  Box a, body;
  a.half_extents = Vector3d(1, 0.5, 0.25), body.half_extents = Vector3d(0.4, 0.75, 0.3);  // (sums exact in binary)
  std::vector<Isometry3d> poses;
  for (int k = 0; k < 400; ++k) {
    Isometry3d p = Isometry3d::Identity();
    switch (k % 5) {
      case 0:  // teleport anywhere
        p.linear() = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
        p.translation() = 3 * Vector3d(u(rng), u(rng), u(rng));
        break;
      case 1:  // the last pose flipped by 180 degrees
        p = poses.back() * Eigen::AngleAxisd(3.14159265358979323846, Vector3d::UnitX());
        break;
      case 2:  // deep inside
        p.translation() = 0.1 * Vector3d(u(rng), u(rng), u(rng));
        break;
      case 3:  // exactly touching face to face: B's -y face on A's +y face
        p.translation() = Vector3d(0.25 * u(rng), 0.5 + 0.75, 0.1 * u(rng));
        break;
      default:  // just apart again
        p.translation() = Vector3d(0, 0.5 + 0.75 + 1e-9 * (1 + u(rng)), 0);
    }
    poses.push_back(p);
  }
  ProximityCache cache;
  for (size_t k = 0; k < poses.size(); ++k) {
    const Box b = placed(body, poses[k]);
    Proximity cold, hot;
    ASSERT_EQ(proximity(a, b, cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(a, b, cache, hot, Want::All), Status::Ok);
    expect_same(cold, hot, 2, false, "box pose " + std::to_string(k));
    if (k % 5 == 3) EXPECT_TRUE(hot.intersecting) << k;  // touching counts as intersecting
  }
  // Shapes: the same poses, with caches spoiled in every way between the calls.
  ConvexShape A, B, C;
  ASSERT_EQ(shape_from_box(a, A), Status::Ok);
  ASSERT_EQ(shape_from_box(body, B), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(128, 9), C), Status::Ok);
  ProximityCache shared;
  for (size_t k = 0; k < poses.size(); ++k) {
    const ConvexShape& other = k % 2 ? B : C;  // one cache for two pairs, alternating
    ProximityCache spoiled;
    spoiled.kind = unsigned(k % 4), spoiled.active = unsigned(rng());
    for (int j = 0; j < 3; ++j) spoiled.a[j] = int(rng() % 300) - 20, spoiled.b[j] = int(rng() % 300) - 20;
    Proximity cold, hot, from_spoiled;
    ASSERT_EQ(proximity(A, Isometry3d::Identity(), other, poses[k], cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(A, Isometry3d::Identity(), other, poses[k], shared, hot, Want::All), Status::Ok);
    ASSERT_EQ(proximity(A, Isometry3d::Identity(), other, poses[k], spoiled, from_spoiled, Want::All), Status::Ok);
    expect_same(cold, hot, 2, false, "shared cache, pose " + std::to_string(k));
    expect_same(cold, from_spoiled, 2, false, "spoiled cache, pose " + std::to_string(k));
    // And a box query handed the shape query's cache.
    Proximity box_cold, box_hot;
    ASSERT_EQ(proximity(a, placed(body, poses[k]), box_cold, Want::All), Status::Ok);
    ASSERT_EQ(proximity(a, placed(body, poses[k]), shared, box_hot, Want::All), Status::Ok);
    expect_same(box_cold, box_hot, 2, false, "box after shape, pose " + std::to_string(k));
    if (testing::Test::HasFailure()) return;
  }
}

// Bad input through the cache: the same status as cold, and the cache left harmless.
TEST(CoherenceAdversarial, BadInputKeepsTheCacheHarmless) {
  ConvexShape A, empty;
  ASSERT_EQ(shape_from_points(tools::icosahedron_points(), A), Status::Ok);
  ProximityCache cache;
  Proximity p;
  Isometry3d far = Isometry3d::Identity();
  far.translation() = Vector3d(5, 0, 0);
  ASSERT_EQ(proximity(A, Isometry3d::Identity(), A, far, cache, p, Want::All), Status::Ok);
  Isometry3d scaled = far;
  scaled.linear() *= 2;
  EXPECT_EQ(proximity(A, Isometry3d::Identity(), A, scaled, cache, p), Status::InvalidPose);
  EXPECT_EQ(proximity(A, Isometry3d::Identity(), empty, far, cache, p), Status::TooFewPoints);
  Box bad;
  bad.half_extents = Vector3d(1, -1, 1);
  EXPECT_EQ(proximity(bad, Box{}, cache, p), Status::InvalidBox);
  Proximity cold, hot;
  far.translation() = Vector3d(1.5, 0.2, 0);
  ASSERT_EQ(proximity(A, Isometry3d::Identity(), A, far, cold, Want::All), Status::Ok);
  ASSERT_EQ(proximity(A, Isometry3d::Identity(), A, far, cache, hot, Want::All), Status::Ok);
  expect_same(cold, hot, 2, false, "after bad input");
}

// Meshes: the seeded search gives the cold distance along a trajectory into contact and out,
// and across teleports; it opens no more pairs than the cold search but for its batches.
TEST(CoherenceMesh, SeededSearchEqualsColdSearch) {
  std::string source;
  const tools::Mesh m = tools::demo_mesh("bun_zipper_res4.ply", source);  // (or its fallbacks)
  Vector3d lo = m.vertices[0], hi = lo;
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const Vector3d centre = (lo + hi) / 2;
  const double size = (hi - lo).norm();
  // A ball 4 % of the mesh's size swinging from its centre to outside it: it crosses the
  // surface on its way out whatever the mesh.
  const tools::Mesh ball = tools::sphere_mesh(0.04 * size, 8);
  Octree A, B;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A), Status::Ok);
  ASSERT_EQ(build_octree(ball.vertices, ball.triangles, B), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  auto path = tools::trajectory(4, 1500, 0.0, 0.7 * size, 0.002 * size);
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1, 1);
  for (size_t k = 0; k < path.size(); k += 97)  // teleports now and then
    path[k].translation() = 0.6 * size * Vector3d(u(rng), u(rng), u(rng));
  ProximityCache cache;
  long contacts = 0;
  for (size_t k = 0; k < path.size(); ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = path[k].linear(), pose.translation() = centre + path[k].translation();
    MeshDistance cold, hot;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, cold), Status::Ok);
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, cache, hot), Status::Ok);
    ASSERT_EQ(hot.intersecting, cold.intersecting) << k;
    ASSERT_NEAR(hot.distance, cold.distance, 1e-12 * size) << k;
    EXPECT_NEAR((hot.point_a - hot.point_b).norm(), hot.distance, 1e-12 * size) << k;
    // (Batches of 16 pairs may flush later in the seeded search: see mesh/distance.cpp's search.)
    EXPECT_LE(hot.stats.node_pairs, cold.stats.node_pairs + 16) << k;
    EXPECT_LE(hot.stats.triangle_pairs, cold.stats.triangle_pairs + 16 * hot.stats.node_pairs) << k;
    contacts += cold.intersecting;
  }
  EXPECT_GT(contacts, 0);
  EXPECT_LT(contacts, long(path.size()));
  EXPECT_GT(cache.warm, long(path.size()) / 2);
  // A cache from another pair, or pointing past the meshes, seeds nothing wrong.
  for (int bad : {-5, 0, 7, 1 << 30}) {
    ProximityCache spoiled;
    spoiled.kind = 3, spoiled.a[0] = bad, spoiled.b[0] = bad;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = centre + Vector3d(0.3 * size, 0, 0);
    MeshDistance cold, hot;
    mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, cold);
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, spoiled, hot), Status::Ok);
    EXPECT_NEAR(hot.distance, cold.distance, 1e-12 * size) << bad;
  }
  // Ties: the mesh against its own copy turned half a turn about the z axis through a corner
  // (exact in binary: the corner maps to itself, so the two touch there), then the same lifted by
  // 1e-9 of the size, from corner to corner: the cached answer is the cold one, and in exact
  // contact intersecting at distance exactly 0.
  MeshWorkspace self;
  make_workspace(A, A, self);
  ProximityCache tie_cache;
  for (size_t v = 0; v < m.vertices.size(); v += m.vertices.size() / 40 + 1) {
    for (const double lift : {0.0, 1e-9 * size}) {
      Eigen::Isometry3d half = Eigen::Isometry3d::Identity();
      half.linear() = Vector3d(-1, -1, 1).asDiagonal();
      half.translation() = Vector3d(2 * m.vertices[v].x(), 2 * m.vertices[v].y(), lift);
      MeshDistance cold, hot;
      ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, half, self, cold), Status::Ok);
      ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, half, self, tie_cache, hot), Status::Ok);
      ASSERT_EQ(hot.intersecting, cold.intersecting) << "corner " << v << " lift " << lift;
      ASSERT_NEAR(hot.distance, cold.distance, 1e-12 * size) << "corner " << v << " lift " << lift;
      if (lift == 0) EXPECT_TRUE(hot.intersecting && hot.distance == 0) << "corner " << v;
    }
  }
}

}  // namespace
}  // namespace minksum
