// minksum against FCL 0.7 (GJK and libccd) on 100,000 random box pairs. FCL's solvers stop at
// a tolerance of 1e-6; wherever one of them disagrees with minksum by more than that, the pair
// goes to the exact brute-force oracle, which must side with minksum (to 1e-9). One pair in 32
// is of lattice boxes (half of them in exact contact), where minksum must equal the exact
// distance and verdict.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>

#include "checks.hpp"
#include "exact_distance.hpp"
#include "ties.hpp"
#include "support/bullet_peer.hpp"
#include "support/fcl_peer.hpp"
#include "support/nanoflann_peer.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

// The exact oracle: brute force on the two boxes as polytopes.
test::Oracle exact(const Box& a, const Box& b) {
  ConvexPolytope A, B;
  polytope_from_box(a, A), polytope_from_box(b, B);
  return test::brute_force(A, B);
}

class VersusFcl : public testing::TestWithParam<int> {};

TEST_P(VersusFcl, DistanceAndPenetration) {
  std::mt19937_64 rng(700 + GetParam());
  int fcl_wrong[2] = {0, 0}, separated = 0, overlapping = 0, depth_checked = 0, depth_wrong = 0;
  int lattice[2] = {0, 0}, fcl_lattice_wrong = 0;
  const int n = test::scaled(25000, 64);
  for (int k = 0; k < n; ++k) {
    Box a = tools::random_box(rng, 2), b = tools::random_box(rng, 2);
    // Every 32nd pair is tie-heavy (tests/ties): lattice boxes, every other one in exact contact.
    if (k % 64 == 63)
      std::tie(a, b) = test::ties::touching_boxes(rng);
    else if (k % 32 == 31)
      a = test::ties::lattice_box(rng, 2, 1), b = test::ties::lattice_box(rng, 2, 1);
    Proximity p;
    ASSERT_EQ(proximity(a, b, p), Status::Ok);
    peers::FclPair pair(a, b);
    if (k % 32 == 31) {
      // The exact oracle: the surfaces' exact distance, and containment where they do not meet.
      ConvexPolytope A, B;
      polytope_from_box(a, A), polytope_from_box(b, B);
      const double gap = test::ties::exact_surface_gap(A, B);
      const bool meet = gap == 0 || test::brute_force(A, B).overlap;
      ASSERT_EQ(p.intersecting, meet) << "lattice pair " << k << ": exact surface gap " << gap;
      ASSERT_NEAR(p.distance, meet ? 0.0 : gap, 1e-12) << "lattice pair " << k;
      if (meet) ASSERT_EQ(p.distance, 0.0) << "lattice pair " << k;
      ++lattice[meet];
      // FCL's verdict (fcl::collide) and, apart, its distance against the exact answer.
      peers::FclAnswer answer;
      const bool fcl_meet = pair.penetration(peers::FclSolver::Gjk, answer);
      if (fcl_meet != meet || (!meet && std::abs(pair.distance(peers::FclSolver::Gjk) - gap) > 1e-6))
        ++fcl_lattice_wrong;
      continue;
    }
    if (!p.intersecting && p.distance > 1e-9) {
      ++separated;
      for (int s = 0; s < 2; ++s) {
        const double d = pair.distance(s ? peers::FclSolver::Libccd : peers::FclSolver::Gjk);
        if (std::abs(d - p.distance) > 1e-6 * (1 + p.distance)) {
          ++fcl_wrong[s];
          // The exact oracle decides: minksum must be right.
          ASSERT_NEAR(p.distance, exact(a, b).distance, 1e-9 * (1 + p.distance)) << "pair " << k;
        }
      }
    } else if (p.penetration_depth > 1e-9) {
      ++overlapping;
      peers::FclAnswer answer;
      if (pair.penetration(peers::FclSolver::Gjk, answer)) {
        ++depth_checked;
        if (std::abs(answer.depth - p.penetration_depth) > 1e-6 * (1 + p.penetration_depth)) {
          ++depth_wrong;  // FCL's depth is not the minimum translation: the SAT decides
          ASSERT_NEAR(p.penetration_depth, exact(a, b).depth, 1e-9) << "pair " << k;
        }
      } else {  // FCL sees no overlap where minksum does: the exact oracle decides
        ++depth_wrong;
        ASSERT_TRUE(exact(a, b).overlap) << "pair " << k;
        ASSERT_NEAR(p.penetration_depth, exact(a, b).depth, 1e-9) << "pair " << k;
      }
    }
  }
  // Both outcomes are exercised, and FCL agrees on most pairs (else the oracle was never
  // really consulted on typical input).
  EXPECT_GT(separated, n / 5);
  EXPECT_GT(overlapping, n / 5);
  EXPECT_LT(fcl_wrong[0] + fcl_wrong[1], separated / 10);
  RecordProperty("separated", separated);
  RecordProperty("fcl_gjk_off_by_more_than_1e-6", fcl_wrong[0]);
  RecordProperty("fcl_libccd_off_by_more_than_1e-6", fcl_wrong[1]);
  RecordProperty("fcl_depth_off_by_more_than_1e-6", depth_wrong);
  EXPECT_GT(lattice[0], 0);
  EXPECT_GT(lattice[1], 0);
  std::printf(
      "shard %d: %d separated (FCL GJK off by > 1e-6: %d, libccd: %d), %d overlapping "
      "(%d FCL depths, %d off by > 1e-6); the exact oracle sided with minksum every time; "
      "lattice pairs apart / meeting %d / %d, all exact (FCL GJK with the other verdict or off by > 1e-6: %d)\n",
      GetParam(), separated, fcl_wrong[0], fcl_wrong[1], overlapping, depth_checked, depth_wrong, lattice[0],
      lattice[1], fcl_lattice_wrong);
}

INSTANTIATE_TEST_SUITE_P(Shards, VersusFcl, testing::Range(0, 4));

// Mesh-mesh distance against FCL's BVH distance (OBBRSS) on two bunny res2 (16,301 triangles;
// a generated mesh where ../shared/data is missing), 200 poses from near contact to apart.
TEST(VersusFclMeshes, BunnyRes2Distance) {
  const auto setup = test::mesh_setup("bun_zipper_res2.ply", 64);
  const tools::Mesh& m = setup->mesh;
  const Octree& A = setup->tree;
  MeshWorkspace& ws = setup->ws;
  peers::FclMeshPair fcl(m.vertices, m.triangles, m.vertices, m.triangles);
  std::mt19937_64 rng(17);
  int separated = 0;
  const int n = std::max(40, test::scaled(200));  // (at least 40: both bands, under the sanitizer too)
  for (int k = 0; k < n; ++k) {
    const Eigen::Isometry3d pose = test::random_pose(rng, 0.12 + 0.2 * k / n);
    MeshDistance got;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, got), Status::Ok);
    const double want = std::max(0.0, fcl.distance(pose));  // FCL reports a collision as <= 0
    ASSERT_NEAR(got.distance, want, 1e-9 * want + 1e-15) << "pose " << k;
    separated += !got.intersecting;
  }
  EXPECT_GT(separated, n / 2);
}

// The point-cloud peer (nanoflann, one bounded nearest-neighbour query per point of the smaller
// cloud) and the octree both equal every pair of points, with the tree on either cloud.
TEST(VersusNanoflann, CloudsEqualBruteForce) {
  const tools::Mesh bunny = test::test_mesh("bun_zipper_res4.ply", 16);
  const tools::Mesh a{tools::sample_surface(bunny, 3000, 1), {}}, b{tools::sample_surface(bunny, 2000, 2), {}};
  Octree A, B;
  ASSERT_EQ(build_octree(a.vertices, A), Status::Ok);
  ASSERT_EQ(build_octree(b.vertices, B), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  peers::NanoflannCloudPair ab(a.vertices, b.vertices), ba(b.vertices, a.vertices);
  std::mt19937_64 rng(23);
  const int n = test::scaled(20, 3);  // (near to far)
  for (int k = 0; k < n; ++k) {
    const Eigen::Isometry3d pose = test::random_pose(rng, 0.02 + 0.2 * k / n);
    const MeshDistance want = tools::brute_distance(a, b, pose, test::exact_triangle_distance);
    MeshDistance got;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, got), Status::Ok);
    EXPECT_NEAR(got.distance, want.distance, 1e-15) << "pose " << k;
    int ia = -1, ib = -1;
    EXPECT_NEAR(ab.distance(pose, &ia, &ib), want.distance, 1e-15) << "pose " << k;
    EXPECT_NEAR((a.vertices[size_t(ia)] - (pose.linear() * b.vertices[size_t(ib)] + pose.translation())).norm(),
                want.distance, 1e-15);
    Eigen::Isometry3d back = Eigen::Isometry3d::Identity();
    back.linear() = pose.linear().transpose(), back.translation() = -(back.linear() * pose.translation());
    EXPECT_NEAR(ba.distance(back), want.distance, 1e-15) << "pose " << k;
  }
}

}  // namespace
}  // namespace minksum

namespace minksum {
namespace {

// Bullet's warm GJK (the trajectory benchmarks' peer) agrees with the coherent queries along
// a trajectory in and out of contact: the distance while apart, the depth (its negative
// distance, by EPA) while overlapping, each to Bullet's own tolerance. Bullet's GJK stops at
// a relative improvement of 1e-6 in the squared distance, its EPA at 1e-4.
TEST(VersusBullet, WarmGjkAlongATrajectory) {
  Box a, body;
  a.half_extents = Eigen::Vector3d(0.5, 0.35, 0.25), body.half_extents = Eigen::Vector3d(0.3, 0.4, 0.2);
  ConvexShape A, B;
  ASSERT_EQ(shape_from_points(tools::icosahedron_points(), A), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::dodecahedron_points(), B), Status::Ok);
  peers::BulletPair boxes(a.half_extents, body.half_extents), shapes(A.polytope(), B.polytope());
  ProximityCache box_cache, shape_cache;
  long apart = 0, overlapping = 0;
  for (int pair = 0; pair < 2; ++pair) {
    const double near = pair == 0 ? 0.6 : 2.8, far = pair == 0 ? 1.5 : 5.0;
    const auto path = tools::trajectory(21 + pair, 3000, near, far, 0.01);
    for (size_t k = 0; k < path.size(); ++k) {
      Proximity ours;
      double theirs;
      if (pair == 0) {
        Box b = body;
        b.center = path[k].translation(), b.rotation = path[k].linear();
        ASSERT_EQ(proximity(a, b, box_cache, ours, Want::Patch), Status::Ok);
        theirs = boxes.distance(Eigen::Isometry3d::Identity(), path[k]);
      } else {
        ASSERT_EQ(proximity(A, Eigen::Isometry3d::Identity(), B, path[k], shape_cache, ours, Want::Patch),
                  Status::Ok);
        theirs = shapes.distance(Eigen::Isometry3d::Identity(), path[k]);
      }
      if (!ours.intersecting && ours.distance > 1e-3) {
        EXPECT_NEAR(theirs, ours.distance, 1e-6 * (1 + ours.distance)) << "pair " << pair << " tick " << k;
        ++apart;
      } else if (ours.intersecting && ours.penetration_depth > 1e-3) {
        EXPECT_NEAR(-theirs, ours.penetration_depth, 1e-4 * (1 + ours.penetration_depth))
            << "pair " << pair << " tick " << k;
        ++overlapping;
      }
      if (testing::Test::HasFailure()) return;
    }
  }
  EXPECT_GT(apart, 1000);
  EXPECT_GT(overlapping, 500);
}

// The exact distance of two shapes' cores (exact triangle distances over their faces; a point or
// segment core as a flat triangle) less their radii, for shapes apart.
double exact_gap(const ConvexShape& a, const Eigen::Isometry3d& pa, const ConvexShape& b, const Eigen::Isometry3d& pb) {
  const auto triangles = [](const ConvexShape& s, const Eigen::Isometry3d& pose) {
    std::vector<std::array<Vector3d, 3>> t;
    const ConvexPolytope& p = s.polytope();
    for (const Face& f : p.faces)
      for (size_t k = 1; k + 1 < f.loop.size(); ++k)
        t.push_back({pose * p.vertices[f.loop[0]], pose * p.vertices[f.loop[k]], pose * p.vertices[f.loop[k + 1]]});
    if (p.faces.empty()) t.push_back({pose * p.vertices.front(), pose * p.vertices.back(), pose * p.vertices.back()});
    return t;
  };
  double least = HUGE_VAL;
  for (const auto& s : triangles(a, pa))
    for (const auto& t : triangles(b, pb)) {
      const Vector3d x[3] = {s[0], s[1], s[2]}, y[3] = {t[0], t[1], t[2]};
      least = std::min(least, test::exact_triangle_distance(x, y));
    }
  return least - a.radius() - b.radius();
}

// Rounded shapes against FCL's spheres and capsules and Bullet's margins, a second opinion
// beside test_radius.cpp's oracles: spheres, capsules, a box and an icosahedron at random
// poses in and out of contact. FCL (GJK, closed forms for its sphere and capsule pairs) gives
// the distance while apart, to its 1e-6; Bullet (each radius its margin; a rounded box as
// btBoxShape grown by its margin) the signed distance, to its GJK's 1e-6 and EPA's 1e-4.
TEST(VersusFclAndBullet, RoundedShapes) {
  struct Operand {
    ConvexShape shape;
    peers::PeerShape peer;
  };
  std::vector<Operand> kinds(5);
  shape_from_sphere(0.5, kinds[0].shape), kinds[0].peer.radius = 0.5;
  shape_from_capsule(0.6, 0.3, kinds[1].shape), kinds[1].peer.kind = peers::PeerShape::Kind::Capsule;
  kinds[1].peer.radius = 0.3, kinds[1].peer.half_length = 0.6;
  Box b;
  b.half_extents = Vector3d(0.5, 0.4, 0.3);
  shape_from_box(b, kinds[2].shape), kinds[2].peer.kind = peers::PeerShape::Kind::Box, kinds[2].peer.half = b.half_extents;
  ConvexShape core;
  shape_from_box(b, core), shape_with_radius(core, 0.2, kinds[3].shape);
  kinds[3].peer = kinds[2].peer, kinds[3].peer.radius = 0.2;
  shape_from_points(tools::scaled(tools::icosahedron_points(), 0.5), kinds[4].shape);
  kinds[4].peer.kind = peers::PeerShape::Kind::Polytope, kinds[4].peer.polytope = kinds[4].shape.polytope();
  std::mt19937_64 rng(57);
  long apart = 0, overlapping = 0, peer_off = 0;
  for (size_t i = 0; i < kinds.size(); ++i)
    for (size_t j = 0; j < kinds.size(); ++j) {
      peers::BulletPair bullet(kinds[i].peer, kinds[j].peer);
      // (FCL has no swept radius: on the rounded box it answers for the core.)
      const double lost = (i == 3 ? 0.2 : 0.0) + (j == 3 ? 0.2 : 0.0);
      peers::PeerShape fa = kinds[i].peer, fb = kinds[j].peer;
      if (i == 3) fa.radius = 0;
      if (j == 3) fb.radius = 0;
      peers::FclPair fcl(fa, fb);
      for (int k = 0; k < 200; ++k) {
        const Eigen::Isometry3d pa = test::random_pose(rng, 0.3), pb = test::random_pose(rng, 1.6);
        Proximity ours;
        ASSERT_EQ(proximity(kinds[i].shape, pa, kinds[j].shape, pb, ours), Status::Ok);
        const double gap = ours.intersecting ? -ours.penetration_depth : ours.distance;
        const double theirs = bullet.distance(pa, pb);
        if (gap > 1e-3) {
          fcl.set_poses(pa, pb);
          const double peer[2] = {fcl.distance(peers::FclSolver::Gjk) - lost, theirs};
          for (double x : peer)
            if (std::abs(x - gap) > 1e-6 * (1 + gap)) {  // (a GJK stopped at its tolerance: the exact cores decide)
              EXPECT_NEAR(exact_gap(kinds[i].shape, pa, kinds[j].shape, pb), gap, 1e-9) << i << " / " << j << " pose " << k;
              ++peer_off;
            }
          ++apart;
        } else if (gap < -1e-3) {
          EXPECT_NEAR(theirs, gap, 1e-4 * (1 - gap)) << i << " / " << j << " pose " << k;
          ++overlapping;
        }
        if (testing::Test::HasFailure()) return;
      }
    }
  EXPECT_GT(apart, 1000);
  EXPECT_GT(overlapping, 500);
  EXPECT_LT(peer_off, apart / 100);  // (the peers' tolerance rarely shows)
}

}  // namespace
}  // namespace minksum
