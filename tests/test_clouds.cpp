// The adaptive octree on meshes of other shapes than the bunny (libcgal-demo's), point clouds and
// degenerate meshes, all against brute force (tools::brute_distance: every pair, skipped only by
// exact sphere bounds; two clouds: plain point-point distances).
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include "checks.hpp"
#include "exact_distance.hpp"
#include "ties.hpp"
#include "support/mesh_io.hpp"

#include <cstdlib>
#include <random>

namespace {

using namespace minksum;
using Eigen::Vector3d;

double diagonal(const tools::Mesh& m) {
  Vector3d lo = Vector3d::Constant(1e300), hi = -lo;
  for (const auto& v : m.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return (hi - lo).norm();
}

// The octree's answer equals brute force: the distance, the verdict, witnesses that realise it.
void expect_brute(const tools::Mesh& ma, const Octree& A, const tools::Mesh& mb, const Octree& B,
                  const Eigen::Isometry3d& pose, MeshWorkspace& ws, const std::string& what) {
  MeshDistance got;
  ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, got), Status::Ok) << what;
  const MeshDistance want = tools::brute_distance(ma, mb, pose, test::exact_triangle_distance);
  const double tol = 1e-12 * (1 + diagonal(ma) + pose.translation().norm());
  ASSERT_NEAR(got.distance, want.distance, tol) << what;
  ASSERT_EQ(got.intersecting, want.intersecting) << what;
  EXPECT_NEAR((got.point_a - got.point_b).norm(), got.distance, tol) << what;
}

// The benchmark's mesh pairs (bench/mesh_bench.cpp), libcgal-demo's meshes scaled to a unit
// diagonal.
const std::vector<std::pair<std::string, std::string>> kPairs = {{"camel.off", "bull.off"},
                                                                 {"femur.off", "turbine.off"},
                                                                 {"fandisk.off", "blade.off"},
                                                                 {"blade.off", "camel.off"},
                                                                 {"turbine.off", "bull.off"}};

// `per_pair` banded poses of every pair (a third in contact, a third within 5 %, a third
// farther), then two touching poses per mesh: a copy turned half a turn about the z axis through
// its highest vertex (exact in binary: the vertex maps to itself), which shares that vertex, and
// the same copy lifted 1e-9 of the size.
// kBunny is the full bunny against itself (the benchmark's first pair; 69K triangles, about
// 5 s of brute force per pose; where ../shared/data is absent, its fallback mesh).
const std::pair<std::string, std::string> kBunny = {"bun_zipper.ply", "bun_zipper.ply"};

// The thin shapes, each against itself: "ribbon" (tools::ribbon_mesh) and "flattened"
// (tools::flattened_mesh, and "flattened_tilted" turned off the axes), at the benchmark's sizes
// (8,000 and 14,160 triangles) with `full`, else at 1,600 and 1,520.
void sweep(const std::vector<std::pair<std::string, std::string>>& pairs, int per_pair, bool full = false) {
  for (const auto& [na, nb] : pairs) {
    tools::Mesh ma, mb;
    if (na == "bun_zipper.ply") {
      ma = mb = test::test_mesh(na, 64);
    } else if (na == "ribbon") {
      ma = mb = tools::ribbon_mesh(full ? 4000 : 800, full ? 8 : 2);
    } else if (na == "flattened") {
      ma = mb = tools::flattened_mesh(full ? 60 : 20);
    } else if (na == "flattened_tilted") {
      ma = mb = tools::tilted(tools::flattened_mesh(full ? 60 : 20));
    } else if (!tools::cgal_demo_mesh(na, ma) || !tools::cgal_demo_mesh(nb, mb)) {
      GTEST_SKIP() << "libcgal-demo is absent";
    }
    Octree A, B;
    ASSERT_EQ(build_octree(ma.vertices, ma.triangles, A), Status::Ok);
    ASSERT_EQ(build_octree(mb.vertices, mb.triangles, B), Status::Ok);
    MeshWorkspace ws;
    make_workspace(A, B, ws);
    const auto poses = tools::banded_poses(A, B, std::min(diagonal(ma), diagonal(mb)), 7, per_pair);
    for (size_t k = 0; k < poses.size(); ++k) {
      expect_brute(ma, A, mb, B, poses[k], ws, na + " " + nb + " pose " + std::to_string(k));
      if (testing::Test::HasFatalFailure()) return;
    }
    MeshWorkspace self;
    make_workspace(A, A, self);
    size_t top = 0;
    for (size_t v = 0; v < ma.vertices.size(); ++v)
      if (ma.vertices[v].z() > ma.vertices[top].z()) top = v;
    Eigen::Isometry3d half = Eigen::Isometry3d::Identity();
    half.linear() = Eigen::Vector3d(-1, -1, 1).asDiagonal();
    half.translation() = Vector3d(2 * ma.vertices[top].x(), 2 * ma.vertices[top].y(), 0);
    MeshDistance touch;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, half, self, touch), Status::Ok);
    EXPECT_EQ(touch.distance, 0.0) << na << " touching its turned copy";
    expect_brute(ma, A, ma, A, half, self, na + " touching");
    half.translation().z() += 1e-9;
    expect_brute(ma, A, ma, A, half, self, na + " 1e-9 apart");
  }
}

// Under the sanitizer (reduced sizes) two of the pairs, still one pose in every band: brute force
// is the cost per case there.
TEST(AdaptiveOctree, EqualsBruteForceOnTheBenchmarkMeshes) {
  auto pairs = kPairs;
  if (test::scaled(10) < 10) pairs.resize(2);
  sweep(pairs, test::scaled(6, 3));
}

const std::vector<std::pair<std::string, std::string>> kThin = {
    {"ribbon", "ribbon"}, {"flattened", "flattened"}, {"flattened_tilted", "flattened_tilted"}};

// Thin and sheet-like shapes, where an axis-aligned cube fits the surface badly at every level:
// a twisted ribbon of slivers (25 to 1) and a closed surface flattened to 1:200, along the axes
// and tilted off them (tools::tilted).
TEST(AdaptiveOctree, EqualsBruteForceOnThinShapes) { sweep(kThin, test::scaled(30, 6)); }

// The full bunny, one pose per band and the touching ones: the full sweep's largest pair, on
// every Release run (about 25 s). Instrumented it would take minutes: the sanitizer run leaves it
// to the Release run, saying so.
TEST(AdaptiveOctree, FullBunnyOnePosePerBand) {
  if (test::scaled(10) < 10) GTEST_SKIP() << "randomized sizes are reduced here (the Release run covers this)";
  sweep({kBunny}, 3);
}

// The full sweep of the closing note: MINKSUM_FULL_SWEEP=1 runs 201 poses per pair of the
// benchmark, the bunny's and the three thin shapes' included (1,809 in all, plus the touching ones);
// without it the test is skipped.
TEST(AdaptiveOctree, FullSweep) {
  if (!std::getenv("MINKSUM_FULL_SWEEP")) GTEST_SKIP() << "set MINKSUM_FULL_SWEEP=1 (about 25 minutes)";
  auto pairs = kPairs;
  pairs.insert(pairs.begin(), kBunny);
  sweep(pairs, 201);
  sweep(kThin, 201, true);
}

// Leaves follow the local density: thin, long or flat parts do not force a global depth.
TEST(AdaptiveOctree, LeavesAreSizedToTheSurface) {
  tools::Mesh m;
  if (!tools::cgal_demo_mesh("camel.off", m)) GTEST_SKIP() << "libcgal-demo is absent";
  Octree tree;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, tree), Status::Ok);
  const OctreeOptions defaults;
  int small = 0;
  double smallest = 1e300, largest = 0;
  for (const auto& n : tree.nodes)
    if (n.first_child < 0) {
      small += n.count <= defaults.leaf_size;
      smallest = std::min(smallest, n.half), largest = std::max(largest, n.half);
    }
  // Every leaf holds at most leaf_size triangles (no two centroids coincide here), and the
  // leaves' cubes differ by 8x or more in size (one global depth would give one size).
  EXPECT_EQ(small, tree.leaves);
  EXPECT_GE(largest / smallest, 8.0);
}

// Clouds sampled from surfaces (so that many points are about as near as any), plus duplicate,
// single, collinear and coplanar clouds, against every pair of points.
TEST(PointCloud, EqualsBruteForce) {
  const tools::Mesh bunny = test::test_mesh("bun_zipper_res4.ply", 16);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  const auto cloud = [](std::vector<Vector3d> pts) { return tools::Mesh{std::move(pts), {}}; };
  std::vector<tools::Mesh> clouds;
  clouds.push_back(cloud(tools::sample_surface(bunny, test::scaled(20000), 1)));
  clouds.push_back(cloud(tools::sample_surface(bunny, 3000, 2)));
  std::vector<Vector3d> dup = tools::sample_surface(bunny, 500, 3);
  dup.insert(dup.end(), dup.begin(), dup.end());  // every point twice
  clouds.push_back(cloud(dup));
  clouds.push_back(cloud({Vector3d(0.01, -0.02, 0.03)}));
  std::vector<Vector3d> line, plane;
  for (int k = 0; k < 700; ++k) line.push_back(Vector3d(1, 2, 3) * (k * 1e-4));
  for (int k = 0; k < 900; ++k) plane.push_back(Vector3d(0.1 * u(rng), 0.1 * u(rng), 0.0));
  clouds.push_back(cloud(line));
  clouds.push_back(cloud(plane));
  std::vector<Octree> trees(clouds.size());
  for (size_t k = 0; k < clouds.size(); ++k) ASSERT_EQ(build_octree(clouds[k].vertices, trees[k]), Status::Ok);
  const int poses = test::scaled(5, 3);  // (near to far)
  for (size_t i = 0; i < clouds.size(); ++i)
    for (size_t j = 0; j < clouds.size(); ++j) {
      MeshWorkspace ws;
      make_workspace(trees[i], trees[j], ws);
      const int n = i == 0 && j == 0 ? 2 : poses;  // 20K x 20K pairs: two poses
      for (int k = 0; k < n; ++k) {
        const Eigen::Isometry3d pose = test::random_pose(rng, 0.02 + 0.2 * k / poses);
        expect_brute(clouds[i], trees[i], clouds[j], trees[j], pose, ws,
                     "clouds " + std::to_string(i) + " " + std::to_string(j) + " pose " + std::to_string(k));
        if (HasFatalFailure()) return;
      }
    }
  // Lattice clouds (1/8 steps within +-1: ties among nearest pairs everywhere) under lattice
  // motions (quarter turns, 1/8 steps), which keep every coordinate exact: from coincident
  // points (contact at distance exactly 0) to apart.
  std::vector<Vector3d> la, lb;
  for (int k = 0; k < 1500; ++k)
    la.push_back(test::ties::lattice_point(rng, 1, 3)), lb.push_back(test::ties::lattice_point(rng, 1, 3));
  Octree LA, LB;
  ASSERT_EQ(build_octree(la, LA), Status::Ok);
  ASSERT_EQ(build_octree(lb, LB), Status::Ok);
  MeshWorkspace lws;
  make_workspace(LA, LB, lws);
  int meet = 0, apart = 0;
  for (int k = 0; k < test::scaled(16, 8); ++k) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = test::ties::quarter_turn(rng);
    pose.translation() = test::ties::lattice_point(rng, 1 + k % 4, 3);
    expect_brute(cloud(la), LA, cloud(lb), LB, pose, lws, "lattice clouds pose " + std::to_string(k));
    if (HasFatalFailure()) return;
    ++(tools::brute_distance(cloud(la), cloud(lb), pose, test::exact_triangle_distance).intersecting ? meet : apart);
  }
  EXPECT_GT(meet, 0);
  EXPECT_GT(apart, 0);
  // A cloud against itself unmoved: every point coincides.
  MeshWorkspace ws;
  make_workspace(trees[2], trees[2], ws);
  MeshDistance d;
  ASSERT_EQ(mesh_distance(trees[2], Eigen::Isometry3d::Identity(), trees[2], Eigen::Isometry3d::Identity(), ws, d),
            Status::Ok);
  EXPECT_EQ(d.distance, 0.0);
  EXPECT_TRUE(d.intersecting);
}

// A cloud against a mesh: the nearest point of the cloud to the surface.
TEST(PointCloud, AgainstAMeshEqualsBruteForce) {
  const tools::Mesh mesh = test::test_mesh("bun_zipper_res3.ply", 24);
  tools::Mesh points{tools::sample_surface(test::test_mesh("bun_zipper_res4.ply", 16), 5000, 4), {}};
  // Ties: every 7th corner of the mesh is a point of the cloud too.
  for (size_t v = 0; v < mesh.vertices.size(); v += 7) points.vertices.push_back(mesh.vertices[v]);
  Octree M, C;
  ASSERT_EQ(build_octree(mesh.vertices, mesh.triangles, M), Status::Ok);
  ASSERT_EQ(build_octree(points.vertices, C), Status::Ok);
  MeshWorkspace mc, cm;
  make_workspace(M, C, mc);
  make_workspace(C, M, cm);
  std::mt19937_64 rng(5);
  const int poses = test::scaled(15, 3);  // (near to far)
  for (int k = 0; k < poses; ++k) {
    const Eigen::Isometry3d pose = test::random_pose(rng, 0.03 + 0.2 * k / poses);
    expect_brute(mesh, M, points, C, pose, mc, "mesh-cloud pose " + std::to_string(k));
    Eigen::Isometry3d back = Eigen::Isometry3d::Identity();  // the same placement seen from the cloud
    back.linear() = pose.linear().transpose(), back.translation() = -(back.linear() * pose.translation());
    expect_brute(points, C, mesh, M, back, cm, "cloud-mesh pose " + std::to_string(k));
    if (HasFatalFailure()) return;
  }
  // Exact contact: in place (the shared points coincide), and turned half a turn about the z
  // axis through a shared corner (exact in binary: the corner maps to itself). Intersecting at
  // distance exactly 0.
  const Vector3d v = mesh.vertices[7 * (mesh.vertices.size() / 14)];
  Eigen::Isometry3d half = Eigen::Isometry3d::Identity();
  half.linear() = Vector3d(-1, -1, 1).asDiagonal(), half.translation() = Vector3d(2 * v.x(), 2 * v.y(), 0);
  for (const Eigen::Isometry3d& pose : {Eigen::Isometry3d::Identity(), half}) {
    MeshDistance got;
    ASSERT_EQ(mesh_distance(M, Eigen::Isometry3d::Identity(), C, pose, mc, got), Status::Ok);
    EXPECT_TRUE(got.intersecting);
    EXPECT_EQ(got.distance, 0.0);
    expect_brute(mesh, M, points, C, pose, mc, "mesh-cloud in exact contact");
  }
}

// Meshes and clouds far apart near the end of the range (coordinates up to 1e100 are accepted):
// a node pair's bound along the centre line squared its gap twice, which overflows past 1e77
// apart, and the infinite bound pruned every pair (fuzz_readers: a distance of inf for three
// points reaching 3.3e97).
TEST(PointCloud, FarApartAtTheEndOfTheRange) {
  const tools::Mesh box = tools::box_mesh(Vector3d(-1, -1, -1), Vector3d(1, 1, 1), 2);
  for (double scale : {1e60, 1e80, 1e99}) {
    tools::Mesh mesh = box, cloud{{Vector3d(0, 0, 0), Vector3d(1, 0, 0.33 * scale), Vector3d(1, 0, 0.25)}, {}};
    for (auto& v : mesh.vertices) v *= 0.1 * scale;  // (apart from its copy at the pose)
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(0.175, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
    pose.translation() = Vector3d(0.3, -0.2, 0.1) * 2 * scale;
    for (const tools::Mesh* m : {&mesh, &cloud}) {
      Octree tree;
      ASSERT_EQ(tools::build_tree(*m, tree), Status::Ok);
      MeshWorkspace ws;
      make_workspace(tree, tree, ws);
      expect_brute(*m, tree, *m, tree, pose, ws, (m == &cloud ? "cloud at " : "mesh at ") + std::to_string(scale));
      MeshDistance d;
      ASSERT_EQ(mesh_distance(tree, Eigen::Isometry3d::Identity(), tree, pose, ws, d), Status::Ok);
      EXPECT_TRUE(std::isfinite(d.distance) && d.distance > 0);
    }
  }
}

TEST(PointCloud, RejectsBadClouds) {
  Octree t;
  EXPECT_EQ(build_octree(std::vector<Vector3d>{}, t), Status::EmptyMesh);
  EXPECT_EQ(build_octree({Vector3d(0, 0, 0), Vector3d(std::nan(""), 0, 0)}, t), Status::NonFinite);
  EXPECT_EQ(build_octree({Vector3d(0, 0, 0), Vector3d(1e300, 0, 0)}, t), Status::OutOfRange);
}

// Zero-area and duplicate triangles, a mesh of one triangle, and a mesh 1e6 from the origin.
TEST(AdaptiveOctree, DegenerateMeshesKeepWorking) {
  const tools::Mesh base = test::test_mesh("bun_zipper_res4.ply", 16);
  tools::Mesh degenerate = base;
  for (size_t k = 0; k < base.triangles.size(); k += 7) {
    const auto& t = base.triangles[k];
    degenerate.triangles.push_back({t[0], t[1], t[1]});  // a segment
    degenerate.triangles.push_back({t[2], t[2], t[2]});  // a point
    degenerate.triangles.push_back(t);                   // a duplicate
    degenerate.vertices.push_back((base.vertices[t[0]] + base.vertices[t[1]]) / 2);
    degenerate.triangles.push_back({t[0], t[1], int(degenerate.vertices.size()) - 1});  // collinear
  }
  tools::Mesh single{{Vector3d(0, 0, 0), Vector3d(0.05, 0, 0), Vector3d(0, 0.05, 0.01)}, {{0, 1, 2}}};
  tools::Mesh far = base;
  for (auto& v : far.vertices) v += Vector3d(1e6, -1e6, 1e6);
  std::mt19937_64 rng(9);
  for (const auto* m : {&degenerate, &single, &far}) {
    Octree A, B;
    ASSERT_EQ(build_octree(m->vertices, m->triangles, A), Status::Ok);
    ASSERT_EQ(build_octree(base.vertices, base.triangles, B), Status::Ok);
    MeshWorkspace ws;
    make_workspace(A, B, ws);
    const Vector3d shift = m == &far ? Vector3d(1e6, -1e6, 1e6) : Vector3d::Zero();
    const int poses = test::scaled(10, 3);  // (near to far)
    for (int k = 0; k < poses; ++k) {
      Eigen::Isometry3d pose = test::random_pose(rng, 0.02 + 0.2 * k / poses);
      pose.translation() += shift;
      expect_brute(*m, A, base, B, pose, ws, "degenerate set, pose " + std::to_string(k));
      if (HasFatalFailure()) return;
    }
  }
}

}  // namespace
