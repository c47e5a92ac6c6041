// Real-time guarantees: no heap allocation inside the kernel calls, the proximity queries of
// boxes, triangles and polytopes, and the mesh queries (the calls a haptics tick makes).
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cstdio>
#include <memory>
#include <array>
#include <random>

#include "haptics/loop.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

// Allocations made while running f (the executable links the CLI's counter, which replaces
// malloc and every operator new). Sanitizer builds do not count (ASan owns malloc): skip there.
template <class F>
long allocations(F&& f) {
  const long before = haptics::allocation_count();
  f();
  return haptics::allocation_count() - before;
}

// Only a sanitizer build links the counter off (examples/CMakeLists.txt says which, at build
// time); everywhere else a counter that does not count fails the tests instead of skipping them.
#define SKIP_UNLESS_COUNTING()                                                                         \
  if (!MINKSUM_ALLOCATIONS_COUNTED) GTEST_SKIP() << "allocations are not counted in sanitizer builds"; \
  ASSERT_GE(haptics::allocation_count(), 0) << "this build links the allocation counter, and it does not count"

TEST(RealTime, CountingWorks) {
  SKIP_UNLESS_COUNTING();
  // The counter must see an allocation, or every zero below would prove nothing.
  EXPECT_GE(allocations([] { auto p = std::make_unique<std::vector<int>>(100); }), 1);
}

TEST(RealTime, KernelsAndQueriesDoNotAllocate) {
  SKIP_UNLESS_COUNTING();
  const Isa active = active_isa();
  std::mt19937_64 rng(1);
  // Set-up: caller-owned buffers, allocated before the loop.
  auto A = std::make_unique<BoxBatch<float, 64>>(), B = std::make_unique<BoxBatch<float, 64>>();
  auto T = std::make_unique<TriangleBatch<float, 64>>();
  auto planes = std::make_unique<BoxBoxPlanes<float, 64>>();
  auto tri_planes = std::make_unique<BoxTrianglePlanes<float, 64>>();
  auto prox = std::make_unique<BoxBoxProximity<float, 64>>();
  auto sep = std::make_unique<BoxBoxSeparation<float, 64>>();
  auto overlap = std::make_unique<BoxTriangleOverlap<float, 64>>();
  auto T2 = std::make_unique<TriangleBatch<float, 64>>();
  auto tri_dist = std::make_unique<TriangleDistances<float, 64>>();
  auto whole = std::make_unique<BoxBoxSum<float, 64>>();
  std::vector<Box> boxes;
  std::vector<Triangle> tris;
  for (int k = 0; k < 64; ++k) {
    boxes.push_back(tools::random_box(rng, 2)), tris.push_back(tools::random_triangle(rng, 2));
    A->set(k, boxes.back()), B->set(k, tools::random_box(rng, 2)), T->set(k, tris.back());
    // Lane 0 spans 1e30: the scalar path's lane, which must not allocate either.
    T2->set(k, k == 0 ? Triangle{{0, 0, 0}, {1e30, 0, 0}, {0, 1e30, 0}} : tools::random_triangle(rng, 2));
  }
  A->count = B->count = T->count = T2->count = 64;
  std::vector<float> x(100, 1.f), y(100, 2.f), z(100, 3.f), d(8, 0.5f), best(8);
  std::vector<int> arg(8);
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!force_isa(isa)) {
      std::printf("NOT TESTED: this CPU lacks %s (its kernels' allocations are not counted here)\n", to_string(isa));
      continue;
    }
    SCOPED_TRACE(to_string(isa));
    EXPECT_EQ(allocations([&] { box_box_planes(*A, *B, true, *planes); }), 0);
    EXPECT_EQ(allocations([&] { box_box_sum(*A, *B, *whole); }), 0);
    EXPECT_EQ(allocations([&] { box_triangle_planes(*A, *T, false, *tri_planes); }), 0);
    EXPECT_EQ(allocations([&] { box_box_proximity(*A, *B, *prox); }), 0);
    EXPECT_EQ(allocations([&] { box_box_separation(*A, *B, *sep); }), 0);
    EXPECT_EQ(allocations([&] { box_triangle_overlap(*A, *T, *overlap); }), 0);
    EXPECT_EQ(allocations([&] { triangle_distance(*T, *T2, *tri_dist); }), 0);
    EXPECT_EQ(allocations([&] {
                support_push(x.data(), y.data(), z.data(), 100, d.data(), d.data(), d.data(), 8, best.data(),
                             arg.data());
              }),
              0);
    BoxBoxPair pair;
    Proximity p;
    KernelPlane tp[26];
    int failed = 0;  // statuses, gathered inside the counts and asserted after them
    EXPECT_EQ(allocations([&] {
                for (int k = 0; k + 1 < 64; ++k) {
                  box_box_planes(boxes[k], boxes[k + 1], false, pair);
                  box_triangle_planes(boxes[k], tris[k], true, tp);
                  failed += proximity(boxes[k], boxes[k + 1], p) != Status::Ok;
                  failed += proximity(boxes[k], tris[k], p) != Status::Ok;
                  failed += proximity(tris[k], tris[k + 1], p) != Status::Ok;
                }
              }),
              0);
    // Polytopes built at set-up (B overlapping, then apart); the query reads them in place.
    ConvexPolytope P, Q[2];
    ASSERT_EQ(polytope_from_points(tools::icosahedron_points(), P), Status::Ok);
    for (int k = 0; k < 2; ++k) {
      std::vector<Eigen::Vector3d> moved;
      for (const auto& v : tools::rotated(tools::dodecahedron_points(), tools::table1_rotation()))
        moved.push_back(v + Eigen::Vector3d(k == 0 ? 0.5 : 5.0, 0.2, 0));
      ASSERT_EQ(polytope_from_points(moved, Q[k]), Status::Ok);
    }
    MinkowskiSum m;  // and the queries on a difference built at set-up
    ASSERT_EQ(minkowski_difference(P, Q[0], m), Status::Ok);
    EXPECT_EQ(allocations([&] {
                for (const ConvexPolytope& q : Q) failed += proximity(P, q, p) != Status::Ok;
                failed += proximity(m, P, Q[0], p) != Status::Ok;
                p.intersecting = contains(m, Eigen::Vector3d::Zero());
                p.penetration_depth = penetration_along(m, Eigen::Vector3d::UnitX());
              }),
              0);
    EXPECT_EQ(failed, 0);
  }
  force_isa(active);
}

// Sums and differences with a reused result: once the result and the per-thread scratch have
// grown to the largest of them, no call allocates, ties or not (aligned boxes, boxes about a
// shared axis, aligned prisms, a box with a prism, two copies, a mirrored pair, coplanar
// faces; the rounded-tie families and copies of rounded points; the generic Table 1 pairs),
// through prepared shapes under poses (each of the parts a caller can ask for) and through the
// polytope entry, which prepares both operands on every call.
TEST(RealTime, SumsDoNotAllocateOnceTheResultHasGrown) {
  SKIP_UNLESS_COUNTING();
  // Every operand pair as shapes and as polytopes; the degenerate ones under one common pose
  // (which keeps their ties), the generic ones with B turned.
  struct Operands {
    ConvexShape a, b;
    ConvexPolytope pa, pb;
    bool difference, common_pose;
  };
  std::vector<tools::DegeneratePair> inputs = tools::degenerate_pairs();
  for (auto& r : tools::rounded_pairs()) inputs.push_back(std::move(r));
  // (and a polytope of rounded points with itself: its normals' exact values come on demand)
  inputs.push_back({"copies_rounded", tools::sphere_points(12, 3), tools::sphere_points(12, 3), false});
  const size_t degenerate = inputs.size();
  for (const auto& t : tools::table1_pairs()) inputs.push_back({t.name, t.a, t.b, false});
  std::vector<Operands> pairs(inputs.size());
  for (size_t k = 0; k < inputs.size(); ++k) {
    Operands& o = pairs[k];
    ASSERT_EQ(shape_from_points(inputs[k].a, o.a), Status::Ok);
    ASSERT_EQ(shape_from_points(inputs[k].b, o.b), Status::Ok);
    ASSERT_EQ(polytope_from_points(inputs[k].a, o.pa), Status::Ok);
    ASSERT_EQ(polytope_from_points(inputs[k].b, o.pb), Status::Ok);
    o.difference = inputs[k].difference, o.common_pose = k < degenerate;
  }
  Eigen::Isometry3d pose_a = Eigen::Isometry3d::Identity(), pose_b = pose_a;
  pose_a.linear() = tools::axis_angle(Eigen::Vector3d(1, -2, 0.5), 0.4);
  pose_a.translation() = Eigen::Vector3d(1, 2, 3);
  pose_b.linear() = tools::table1_rotation();
  MinkowskiSum m;
  int facets = 0;
  const auto run_all = [&] {
    for (const Operands& o : pairs) {
      const Eigen::Isometry3d& pb = o.common_pose ? pose_a : pose_b;
      bool posed_ok = true;
      for (const SumParts parts : {SumParts::Planes, SumParts::Vertices, SumParts::Whole}) {
        const Status s = o.difference ? minkowski_difference(o.a, pose_a, o.b, pb, m, parts)
                                      : minkowski_sum(o.a, pose_a, o.b, pb, m, parts);
        posed_ok = posed_ok && s == Status::Ok && !m.corrected;
      }
      facets += m.F;
      const Status t = o.difference ? minkowski_difference(o.pa, o.pb, m) : minkowski_sum(o.pa, o.pb, m);
      if (!posed_ok || t != Status::Ok || m.corrected) facets = -1000000;  // (no assertion inside the count)
      facets += m.F;
    }
  };
  run_all();  // set-up: the result and the scratch grow
  ASSERT_GT(facets, 0);
  facets = 0;
  EXPECT_EQ(allocations([&] { run_all(), run_all(); }), 0);
  EXPECT_GE(facets, 4 * 6 * int(pairs.size()));  // every sum was made (6 facets or more), none by the corrector
  Box a, b;                                      // and the box-box entry on aligned boxes (its general path)
  b.half_extents = Eigen::Vector3d(0.5, 2, 0.25);
  ASSERT_EQ(minkowski_sum(a, b, m), Status::Ok);
  EXPECT_EQ(allocations([&] { minkowski_sum(a, b, m); }), 0);
  EXPECT_EQ(m.F, 6);
}

// The bunny res4 and its octree, with a workspace for queries against itself, made at set-up.
struct Res4 {
  Octree tree;
  MeshWorkspace ws;
  Res4() {
    std::string source;
    const tools::Mesh m = tools::demo_mesh("bun_zipper_res4.ply", source);
    build_octree(m.vertices, m.triangles, tree);
    make_workspace(tree, tree, ws);
  }
};

// The mesh-mesh query with a workspace made at set-up: no allocation on any pose.
TEST(RealTime, MeshDistanceDoesNotAllocate) {
  SKIP_UNLESS_COUNTING();
  Res4 bunny;
  ASSERT_FALSE(bunny.tree.nodes.empty());
  const Octree& A = bunny.tree;
  MeshWorkspace& ws = bunny.ws;
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Isometry3d> poses(50);
  for (auto& p : poses) {
    p.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    p.translation() = 0.2 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  MeshDistance d;
  long pairs = 0;
  EXPECT_EQ(allocations([&] {
              for (const Eigen::Isometry3d& p : poses)
                mesh_distance(A, Eigen::Isometry3d::Identity(), A, p, ws, d), pairs += d.stats.triangle_pairs;
            }),
            0);
  EXPECT_GT(pairs, 50);  // the queries did real work
}

// The cold entry points on the real-time path: posed shapes without a cache (every Want), and
// mesh_contact of a box tool turned by a new rotation on every call, centred on the bunny's
// vertices so that most calls clip triangles. Statuses are gathered inside the count and
// asserted after it, with proof that the calls did real work.
TEST(RealTime, UncachedShapeQueriesAndMeshContactDoNotAllocate) {
  SKIP_UNLESS_COUNTING();
  ConvexShape A, B, tool;
  ASSERT_EQ(shape_from_points(tools::icosahedron_points(), A), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(64, 3), B), Status::Ok);
  Box box;
  box.half_extents = Eigen::Vector3d(0.01, 0.006, 0.004);
  ASSERT_EQ(shape_from_box(box, tool), Status::Ok);
  std::string source;
  const tools::Mesh mesh = tools::demo_mesh("bun_zipper_res4.ply", source);
  Octree M;
  MeshWorkspace ws;
  ASSERT_EQ(build_octree(mesh.vertices, mesh.triangles, M), Status::Ok);
  make_workspace(M, M, ws);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Isometry3d> tool_poses(100);
  for (size_t k = 0; k < tool_poses.size(); ++k) {
    tool_poses[k].linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    tool_poses[k].translation() = mesh.vertices[k * 7 % mesh.vertices.size()];
  }
  const auto path = tools::trajectory(4, 300, 0.5, 3.5, 0.02);
  Proximity p;
  MeshContact c;
  int failed = 0, intersecting = 0, separated = 0, touched = 0;
  EXPECT_EQ(allocations([&] {
              for (const Eigen::Isometry3d& pose : path)
                for (Want want : {Want::All, Want::Verdict, Want::Distance, Want::Witnesses, Want::Patch, Want::MaxDistance}) {
                  failed += proximity(A, Eigen::Isometry3d::Identity(), B, pose, p, want) != Status::Ok;
                  (p.intersecting ? intersecting : separated) += 1;
                }
              for (const Eigen::Isometry3d& pose : tool_poses) {
                failed += mesh_contact(M, Eigen::Isometry3d::Identity(), tool, pose, ws, c) != Status::Ok;
                touched += c.intersecting;
              }
            }),
            0);
  EXPECT_EQ(failed, 0);
  EXPECT_GT(intersecting, 30);  // the trajectory runs through contact and apart
  EXPECT_GT(separated, 30);
  EXPECT_GT(touched, 50);  // most tools on a vertex cut its triangles
}

// Rounded shapes (spheres, capsules, a rounded box, against an icosahedron and each other):
// proximity cold and coherent at every level, the contact patch, the time of impact and the
// mesh sweep, the shape form of mesh distance and mesh contact with a rounded tool, along a path
// in and out of contact: no allocation.
TEST(RealTime, RoundedShapesDoNotAllocate) {
  SKIP_UNLESS_COUNTING();
  ConvexShape sphere, capsule, box, rounded_box, icosa;
  ASSERT_EQ(shape_from_sphere(0.5, sphere), Status::Ok);
  ASSERT_EQ(shape_from_capsule(0.6, 0.3, capsule), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, box), Status::Ok);
  ASSERT_EQ(shape_with_radius(box, 0.2, rounded_box), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::icosahedron_points(), icosa), Status::Ok);
  Octree mesh;
  std::vector<std::array<int, 3>> faces;
  for (const Face& f : icosa.polytope().faces) faces.push_back({f.loop[0], f.loop[1], f.loop[2]});
  ASSERT_EQ(build_octree(icosa.polytope().vertices, faces, mesh), Status::Ok);
  const ConvexShape* shapes[] = {&sphere, &capsule, &rounded_box, &icosa};
  const auto path = tools::trajectory(6, 100, 0.5, 3.5, 0.05);
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  ProximityCache caches[4][4];
  Proximity p;
  ContactPatch patch;
  TimeOfImpact t;
  MeshWorkspace ws;
  make_workspace(mesh, mesh, ws);
  ProximityCache mesh_caches[4];
  MeshDistance d;
  MeshContact c;
  int failed = 0, intersecting = 0, hits = 0, touched = 0;
  EXPECT_EQ(allocations([&] {
              for (size_t k = 0; k + 1 < path.size(); ++k)
                for (int i = 0; i < 4; ++i)
                  for (int j = 0; j < 4; ++j) {
                    const ConvexShape &a = *shapes[i], &b = *shapes[j];
                    for (Want want : {Want::All, Want::Verdict, Want::Witnesses})
                      failed += proximity(a, I, b, path[k], p, want) != Status::Ok;
                    failed += proximity(a, I, b, path[k], caches[i][j], p) != Status::Ok;
                    intersecting += p.intersecting;
                    const Status s = contact_patch(a, I, b, path[k], 0.1, patch);
                    failed += s != Status::Ok && s != Status::CapacityExceeded;
                    failed += time_of_impact(a, I, I, b, path[k], path[k + 1], t) != Status::Ok;
                    if (i == 0) {
                      failed += time_of_impact(mesh, I, b, path[k], path[k + 1], t) != Status::Ok;
                      hits += t.hit;
                      // The shape form of mesh_distance, cold and cached, and mesh contact (a
                      // rounded polytope among them).
                      failed += mesh_distance(mesh, I, b, path[k], d) != Status::Ok;
                      failed += mesh_distance(mesh, I, b, path[k], mesh_caches[j], d) != Status::Ok;
                      const Status cs = mesh_contact(mesh, I, b, path[k], ws, c);
                      failed += cs != Status::Ok;
                      touched += c.intersecting;
                    }
                  }
            }),
            0);
  EXPECT_EQ(failed, 0);
  EXPECT_GT(intersecting, 100);  // the path runs through contact
  EXPECT_GT(hits, 0);
  EXPECT_GT(touched, 0);  // (the path touches the mesh: contact did work)
}

// The coherent entry points, along a trajectory with caches made at set-up: no allocation, and
// the caches were used (else the zero proves nothing about the warm paths).
TEST(RealTime, CoherentQueriesDoNotAllocate) {
  SKIP_UNLESS_COUNTING();
  ConvexShape A, B;
  ASSERT_EQ(shape_from_points(tools::icosahedron_points(), A), Status::Ok);
  ASSERT_EQ(shape_from_points(tools::sphere_points(64, 3), B), Status::Ok);
  Box a, body;
  a.half_extents = Eigen::Vector3d(0.5, 0.3, 0.2), body.half_extents = Eigen::Vector3d(0.3, 0.4, 0.25);
  const Triangle tri{Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.9, 0.1, 0), Eigen::Vector3d(0.2, 0.7, 0.1)};
  const auto path = tools::trajectory(3, 600, 0.5, 3.5, 0.02);
  Res4 bunny;
  ASSERT_FALSE(bunny.tree.nodes.empty());
  const Octree& M = bunny.tree;
  MeshWorkspace& ws = bunny.ws;
  ProximityCache boxes, box_tri, shapes, meshes;
  Proximity p;
  MeshDistance d;
  EXPECT_EQ(allocations([&] {
              for (const Eigen::Isometry3d& pose : path) {
                Box b = body;
                b.center = pose.translation(), b.rotation = pose.linear();
                proximity(a, b, boxes, p);
                proximity(a, Triangle{pose * tri.a, pose * tri.b, pose * tri.c}, box_tri, p);
                proximity(A, Eigen::Isometry3d::Identity(), B, pose, shapes, p);
                Eigen::Isometry3d mp = Eigen::Isometry3d::Identity();
                mp.linear() = pose.linear(), mp.translation() = 0.05 * pose.translation();
                mesh_distance(M, Eigen::Isometry3d::Identity(), M, mp, ws, meshes, d);
                // The tool's time of impact against the mesh, from 0.1 above the pose to it, turning.
                TimeOfImpact toi;
                time_of_impact(M, Eigen::Isometry3d::Identity(), A, Eigen::Translation3d(0, 0, 0.1) * mp,
                               mp * Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()), toi);
              }
            }),
            0);
  for (const ProximityCache* c : {&boxes, &box_tri, &shapes, &meshes}) EXPECT_GT(c->warm, 100);
}

// Face to face (tools::face_pairs: boxes, prisms, a box on a prism, a flat face on a box, an
// edge along a face), apart, touching and pressed, flat and rocking, cold and coherent: the
// verdict, the plain and the patch witnesses, the touching certificate, the face probe and the
// contact patch (cold, coherent and reduced) work in fixed buffers.
TEST(RealTime, FaceToFaceQueriesDoNotAllocate) {
  SKIP_UNLESS_COUNTING();
  const Eigen::Isometry3d pose_a(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized()));
  for (const auto& pair : tools::face_pairs()) {
    ConvexShape A, B;
    ASSERT_EQ(pair.a_is_box ? shape_from_box(pair.box_a, A) : shape_from_points(pair.a, A), Status::Ok);
    ASSERT_EQ(pair.b_is_box ? shape_from_box(pair.box_b, B) : shape_from_points(pair.b, B), Status::Ok);
    for (double gap : {1e-3, 0.0, -1e-3})
      for (bool rocking : {false, true}) {
        ProximityCache cache, patch_cache;
        Proximity p;
        ContactPatch patch;
        EXPECT_EQ(allocations([&] {
                    for (int k = 0; k < 64; ++k) {
                      const Eigen::Isometry3d pose_b = pose_a * tools::face_pose(pair, k, 64, gap, rocking);
                      for (Want want : {Want::Verdict, Want::Witnesses, Want::Patch}) {
                        proximity(A, pose_a, B, pose_b, p, want);
                        proximity(A, pose_a, B, pose_b, cache, p, want);
                      }
                      contact_patch(A, pose_a, B, pose_b, 2e-3, patch);
                      contact_patch(A, pose_a, B, pose_b, 2e-3, patch_cache, patch);
                      reduce_contact_patch(patch);
                      // B falling onto A from 0.5 above through the pose, turning on odd ticks.
                      TimeOfImpact toi;
                      const Eigen::Isometry3d from = pose_b * Eigen::Translation3d(0, 0, 0.5);
                      const Eigen::Isometry3d to = (k % 2 ? pose_b * Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX())
                                                          : pose_b) *
                                                   Eigen::Translation3d(0, 0, -0.5);
                      time_of_impact(A, pose_a, pose_a, B, from, to, toi);
                    }
                  }),
                  0)
            << pair.name << " gap " << gap << (rocking ? " rocking" : "");
      }
  }
}

// A short 6-DOF haptic loop (two 4 s path cycles at 1 kHz) for each convex tool: nothing
// allocated or thrown after warm-up; no force while the proxy is apart; pressing in pushes the
// device back out and up (the press is straight down onto the scene's highest point). The box
// presses a face onto the surface: there the depth moves continuously along the path, and so
// do the force and the torque in steady contact. (The icosahedron touches by a vertex: its
// patch is the facet under that vertex, and on the coarse bunny (2 mm facets under a 2 mm
// press) the contact normal turns by a crease's angle when the vertex crosses an edge, and the
// force with it.)
TEST(RealTime, HapticLoop) {
  for (const std::string tool : {"box", "icosa", "sphere:5", "capsule:8:4"}) {
    SCOPED_TRACE(tool);
    haptics::Options o;
    o.tool = tool, o.seconds = 8, o.warmup = 500;
    haptics::Report r;
    std::string error;
    ASSERT_TRUE(haptics::run(o, haptics::allocation_count, r, error)) << error;
    EXPECT_EQ(r.ticks, 8000);
    if (MINKSUM_ALLOCATIONS_COUNTED) EXPECT_EQ(r.allocations, 0);  // (sanitizer builds do not count)
    EXPECT_EQ(r.exceptions, 0);
    EXPECT_GT(r.contacts, 1000);  // both phases happen
    EXPECT_LT(r.contacts, 7000);
    double max_jump = 0, max_depth = 0, max_force = 0, max_torque = 0;
    for (long k = 0; k < r.ticks; ++k) {
      if (r.distance[k] > 0) EXPECT_EQ(r.force[k], 0) << "tick " << k;
      if (r.depth[k] > 0.001) {  // pressing in: pushed out, and up
        EXPECT_GT(r.force_dot_normal[k], 0) << "tick " << k;
        EXPECT_GT(r.force_up[k], 0.5 * r.force[k]) << "tick " << k;
      }
      if (k > 0) max_jump = std::max(max_jump, std::abs(r.depth[k] - r.depth[k - 1]));
      max_depth = std::max(max_depth, r.depth[k]);
      max_force = std::max(max_force, r.force[k]), max_torque = std::max(max_torque, r.torque[k]);
    }
    EXPECT_GT(max_depth, 0.0015);  // the 2 mm press was felt
    EXPECT_GT(max_force, 3.0);
    if (tool == "sphere:5") EXPECT_LT(r.max_force_jump, 0.1 * max_force);  // (the distance's gradient: continuous)
    if (tool != "box") continue;
    // The path moves at most 0.1 mm per tick; the depth may not jump by more than that.
    EXPECT_LT(max_jump, 1e-4);
    // Steady contact: the spring stretches by at most the path's step a tick (0.1 N at 2 kN/m)
    // and the patch's normal and centre move with the proxy. A proxy that lifts off a surface
    // as it slides, or a patch whose centre hops between triangles, jumps by the whole force.
    EXPECT_GT(max_torque, 1e-3);  // the slide and the turn move the patch off the device's axis
    EXPECT_LT(r.max_force_jump, 0.1 * max_force);
    EXPECT_LT(r.max_torque_jump, 0.05 * max_torque);
  }
}

// A device plunging through a sheet 0.5 mm thick at 1, 3 and 10 m/s (0.5 mm to 5 times the
// sheet's thickness a tick), 5 mm past its top: the proxy never enters the sheet, and from the
// first tick of contact on the force pushes the device back up by at least the spring's
// stretch from the sheet's top (the proxy rests a skin above it).
TEST(RealTime, HapticProxyDoesNotTunnelThroughAThinSheet) {
  // The box's bottom is 8 mm below its origin, the default sphere's 5 mm.
  for (const auto& [tool, lift] : {std::pair{std::string("box"), 0.008}, std::pair{std::string("sphere:5"), 0.005}})
    for (double speed : {1.0, 3.0, 10.0}) {
      SCOPED_TRACE(tool + ", speed " + std::to_string(speed) + " m/s");
      haptics::Options o;
      o.tool = tool, o.scene = "sheet", o.speed = speed, o.press = 0.005, o.seconds = 0.5, o.warmup = 0;
      haptics::Report r;
      std::string error;
      ASSERT_TRUE(haptics::run(o, haptics::allocation_count, r, error)) << error;
      double deepest = 0;
      long pushed = 0;
      for (long k = 0; k < r.ticks; ++k) {
        EXPECT_GE(r.proxy_y[k] - lift, -1e-9) << "tick " << k << ": the proxy entered the sheet";
        const double below = -(r.device_y[k] - lift);  // the device's bottom under the sheet's top
        deepest = std::max(deepest, below);
        if (below > 0 && k > 0 && r.device_y[k - 1] - lift < 0) {
          EXPECT_GE(r.force_up[k], 0.999 * o.stiffness * below) << "tick " << k;
          ++pushed;
        }
      }
      EXPECT_GT(deepest, 0.0045);  // the device did go through (the sheet's bottom is at 0.5 mm)
      EXPECT_GT(pushed, 400);
    }
}

// Whether the segment p q crosses the triangle t (Moller and Trumbore's test, in doubles: the
// slack of the shrunk tool below covers its rounding).
bool crosses(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d* t) {
  const Eigen::Vector3d d = q - p, e1 = t[1] - t[0], e2 = t[2] - t[0], h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-300) return false;
  const Eigen::Vector3d s = p - t[0], g = s.cross(e1);
  const double u = s.dot(h) / det, v = d.dot(g) / det, w = e2.dot(g) / det;
  return u >= 0 && v >= 0 && u + v <= 1 && w >= 0 && w <= 1;
}

// Whether the segment p q (in the box's frame) meets the box of half extents h (slabs).
bool meets_box(const Eigen::Vector3d& p, const Eigen::Vector3d& q, const Eigen::Vector3d& h) {
  double in = 0, out = 1;
  for (int i = 0; i < 3; ++i) {
    const double d = q[i] - p[i];
    if (d == 0) {
      if (std::abs(p[i]) > h[i]) return false;
      continue;
    }
    const double s0 = (-h[i] - p[i]) / d, s1 = (h[i] - p[i]) / d;
    in = std::max(in, std::min(s0, s1)), out = std::min(out, std::max(s0, s1));
    if (in > out) return false;
  }
  return true;
}

// Whether the box tool at each traced tick of r stays out of the scene by more than its sweeps'
// tolerance (haptics::kProxyTolerance, the band's contract). Checked without the library: the
// box shrunk by that tolerance meets no scene triangle (its edges cross none, no scene edge
// meets it). Counts the ticks turned by over 0.05 rad and those in contact.
void expect_box_proxy_outside(const haptics::Report& r, long& turning, long& touching) {
  std::string source;
  const tools::Mesh scene = tools::demo_mesh(r.scene_mesh, source);
  const Eigen::Vector3d half = Eigen::Vector3d(0.010, 0.008, 0.006) - Eigen::Vector3d::Constant(haptics::kProxyTolerance);
  for (size_t k = 0; k < r.proxy.size(); ++k) {
    const Eigen::Isometry3d& pose = r.proxy[k];
    const Eigen::Isometry3d inverse = pose.inverse();
    turning += Eigen::AngleAxisd(pose.linear()).angle() > 0.05;
    touching += r.depth[k] > 0 || r.distance[k] == 0;
    Eigen::Vector3d corner[8];
    for (int c = 0; c < 8; ++c)
      corner[c] = pose * Eigen::Vector3d(c & 1 ? half.x() : -half.x(), c & 2 ? half.y() : -half.y(),
                                         c & 4 ? half.z() : -half.z());
    for (const auto& tri : scene.triangles) {
      const Eigen::Vector3d t[3] = {scene.vertices[size_t(tri[0])], scene.vertices[size_t(tri[1])],
                                    scene.vertices[size_t(tri[2])]};
      if ((t[0] - pose.translation()).norm() > 0.03 + (t[1] - t[0]).norm() + (t[2] - t[0]).norm()) continue;
      bool meet = false;
      for (int c = 0; c < 8 && !meet; ++c)
        for (int axis = 1; axis < 8 && !meet; axis <<= 1)
          if (!(c & axis)) meet = crosses(corner[c], corner[c | axis], t);
      for (int e = 0; e < 3 && !meet; ++e) meet = meets_box(inverse * t[e], inverse * t[(e + 1) % 3], half);
      ASSERT_FALSE(meet) << "tick " << k << ": the proxy is in the scene by more than " << haptics::kProxyTolerance
                         << " (" << source << ")";
    }
  }
}

// The 6-DOF proxy over a whole path cycle (the approach, the 2 mm press, the slide there and
// back turning by up to 0.4 rad, the lift) stays out of the scene (expect_box_proxy_outside).
TEST(RealTime, HapticProxyStaysOutOfTheSceneWhileTurning) {
  haptics::Options o;
  o.tool = "box", o.seconds = 4, o.warmup = 0;
  haptics::Report r;
  std::string error;
  ASSERT_TRUE(haptics::run(o, haptics::allocation_count, r, error)) << error;
  long turning = 0, touching = 0;
  expect_box_proxy_outside(r, turning, touching);
  EXPECT_GT(turning, 500);  // the turning slide was run
  EXPECT_GT(touching, 1000);
}

// Turning in place just above the surface (40 um, within the contact's two skins), neither
// pressed nor sliding: every move is a turn, which only the turn's term of the proxy's Mirtich
// bound (angle times the tool's reach) keeps from being made without a sweep. (A slide's or a
// press's sweeps re-certify the clearance every tick or few, which hides a bound without that
// term in the test above.)
TEST(RealTime, HapticProxyStaysOutOfTheSceneTurningInPlace) {
  haptics::Options o;
  o.tool = "box", o.seconds = 4, o.warmup = 0, o.press = -4e-5, o.slide = 0;
  haptics::Report r;
  std::string error;
  ASSERT_TRUE(haptics::run(o, haptics::allocation_count, r, error)) << error;
  long turning = 0, touching = 0;
  expect_box_proxy_outside(r, turning, touching);
  EXPECT_GT(turning, 500);
  EXPECT_GT(touching, 1000);  // (it turned on the surface, not above it)
}

// The distance of point p to triangle t (its plane where p projects inside, else its edges).
double point_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d* t) {
  const auto edge = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    const double s = std::clamp((p - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
    return (a + s * (b - a) - p).norm();
  };
  const Eigen::Vector3d n = (t[1] - t[0]).cross(t[2] - t[0]).normalized();
  const Eigen::Vector3d q = p - n.dot(p - t[0]) * n;
  bool inside = true;
  for (int k = 0; k < 3; ++k) inside = inside && (t[(k + 1) % 3] - t[k]).cross(q - t[k]).dot(n) >= 0;
  if (inside) return std::abs(n.dot(p - t[0]));
  return std::min({edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])});
}

// The distance of segments p0 p1 and q0 q1 (Ericson 5.1.9; neither degenerate here).
double segment_segment(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                       const Eigen::Vector3d& q1) {
  const Eigen::Vector3d d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r), c = d1.dot(r), b = d1.dot(d2);
  const double den = a * e - b * b;
  double s = den > 1e-300 ? std::clamp((b * f - c * e) / den, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) t = 0, s = std::clamp(-c / a, 0.0, 1.0);
  if (t > 1) t = 1, s = std::clamp((b - c) / a, 0.0, 1.0);
  return (p0 + s * d1 - q0 - t * d2).norm();
}

// The rounded tools over a whole path cycle: on no tick does the core come nearer a scene
// triangle than the radius less the sweeps' tolerance. Checked without the library: the core's
// ends against the triangle, its segment against the triangle's edges, and through it.
TEST(RealTime, RoundedHapticProxyStaysOutOfTheScene) {
  for (const auto& [tool, h, radius] : {std::tuple{std::string("sphere:5"), 0.0, 0.005},
                                        std::tuple{std::string("capsule:8:4"), 0.008, 0.004}}) {
    SCOPED_TRACE(tool);
    haptics::Options o;
    o.tool = tool, o.seconds = 4, o.warmup = 0;
    haptics::Report r;
    std::string error, source;
    ASSERT_TRUE(haptics::run(o, haptics::allocation_count, r, error)) << error;
    const tools::Mesh scene = tools::demo_mesh(r.scene_mesh, source);
    long touching = 0;
    double nearest = 1;
    for (long k = 0; k < r.ticks; ++k) {
      const Eigen::Isometry3d& pose = r.proxy[size_t(k)];
      touching += r.depth[size_t(k)] > 0;
      const Eigen::Vector3d s0 = pose * Eigen::Vector3d(0, 0, -h), s1 = pose * Eigen::Vector3d(0, 0, h);
      for (const auto& tri : scene.triangles) {
        const Eigen::Vector3d t[3] = {scene.vertices[size_t(tri[0])], scene.vertices[size_t(tri[1])],
                                      scene.vertices[size_t(tri[2])]};
        if ((t[0] - pose.translation()).norm() > 0.02 + (t[1] - t[0]).norm() + (t[2] - t[0]).norm()) continue;
        if ((t[1] - t[0]).cross(t[2] - t[0]).norm() == 0) continue;  // (a degenerate triangle: its edges count)
        double d = std::min(point_triangle(s0, t), point_triangle(s1, t));
        if (h > 0) {
          for (int e = 0; e < 3; ++e) d = std::min(d, segment_segment(s0, s1, t[e], t[(e + 1) % 3]));
          if (crosses(s0, s1, t)) d = 0;
        }
        nearest = std::min(nearest, d);
        ASSERT_GE(d, radius - haptics::kProxyTolerance - 1e-12) << "tick " << k << ": the proxy is in the scene";
      }
    }
    EXPECT_GT(touching, 1000);
    EXPECT_LT(nearest, radius + 1e-4);  // it did rest on the scene
  }
}

}  // namespace
}  // namespace minksum
