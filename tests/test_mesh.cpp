// Mesh-mesh distance through octrees against all-pairs brute force (an independent traversal:
// every triangle pair), and the triangle-triangle distance against the general convex path
// (the Minkowski difference of the two triangles); bad input; the octree's leaf invariant.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <tuple>
#include <set>

#include "checks.hpp"
#include "exact_distance.hpp"
#include "ties.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

// Distance of p from triangle t (for checking witnesses).
double off_triangle(const tools::Mesh& m, int t, const Vector3d& p, const Eigen::Isometry3d& pose) {
  Vector3d v[3];
  for (int k = 0; k < 3; ++k) v[k] = pose.linear() * m.vertices[m.triangles[t][k]] + pose.translation();
  const Vector3d pt[3] = {p, p, p};
  Vector3d a, b;
  return triangle_distance(v, pt, a, b);
}

// Octree query == brute force on `poses` random poses from overlapping to well apart.
void check_against_brute_force(const std::string& name, int rings, int poses, unsigned seed) {
  const auto setup = test::mesh_setup(name, rings);
  const tools::Mesh& m = setup->mesh;
  const Octree& A = setup->tree;
  MeshWorkspace& ws = setup->ws;
  std::mt19937_64 rng(seed), world_rng(seed + 1);
  int intersecting = 0;
  for (int k = 0; k < poses; ++k) {
    const Eigen::Isometry3d pose = test::random_pose(rng, 0.05 + 0.25 * k / poses);
    MeshDistance got;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, got), Status::Ok);
    const MeshDistance want = tools::brute_distance(m, m, pose, test::exact_triangle_distance);
    ASSERT_NEAR(got.distance, want.distance, 1e-12) << "pose " << k;
    ASSERT_EQ(got.intersecting, want.intersecting) << "pose " << k;
    intersecting += got.intersecting;
    // The witnesses realise the distance and lie on the triangles named.
    EXPECT_NEAR((got.point_a - got.point_b).norm(), got.distance, 1e-12) << "pose " << k;
    EXPECT_LE(off_triangle(m, got.triangle_a, got.point_a, Eigen::Isometry3d::Identity()), 1e-12) << "pose " << k;
    EXPECT_LE(off_triangle(m, got.triangle_b, got.point_b, pose), 1e-12) << "pose " << k;
    EXPECT_GT(got.stats.candidates_a, 0);
    // Both meshes moved by one rigid motion W (world poses): the same distance, with witnesses
    // on the moved triangles.
    const Eigen::Isometry3d W = test::random_pose(world_rng, 1.0);
    MeshDistance moved;
    ASSERT_EQ(mesh_distance(A, W, A, W * pose, ws, moved), Status::Ok);
    EXPECT_NEAR(moved.distance, got.distance, 1e-12) << "pose " << k;
    EXPECT_EQ(moved.intersecting, got.intersecting) << "pose " << k;
    EXPECT_LE(off_triangle(m, moved.triangle_a, moved.point_a, W), 1e-12) << "pose " << k;
    EXPECT_LE(off_triangle(m, moved.triangle_b, moved.point_b, W * pose), 1e-12) << "pose " << k;
    if (testing::Test::HasFailure()) return;
  }
  // The sweep must cover both kinds, or half of the claim went untested.
  EXPECT_GT(intersecting, poses / 20);
  EXPECT_LT(intersecting, poses - poses / 20);
}

// MINKSUM_MESH_POSES overrides the number of poses (the closing note's longer runs).
int poses_from_env(int fallback) {
  const char* s = std::getenv("MINKSUM_MESH_POSES");
  return s ? std::atoi(s) : test::scaled(fallback);
}

TEST(MeshDistance, EqualsBruteForceOnBunnyRes4) {
  check_against_brute_force("bun_zipper_res4.ply", 16, poses_from_env(1000), 11);
}

TEST(MeshDistance, EqualsBruteForceOnBunnyRes3) {
  check_against_brute_force("bun_zipper_res3.ply", 31, poses_from_env(150), 12);
}

// Tie-heavy poses (tests/ties) on a bunny whose corners are rounded to a 2^-16 lattice: quarter
// turns and lattice offsets keep every coordinate exact, so faces, edges and corners of the copy
// land exactly on the original's. Every other pose turns the copy about one of its own corners,
// which the two then share: exact contact, where the answer must be intersecting at distance
// exactly 0. The rest is checked against brute force; within rounding of contact, the exact
// distance of the pair brute force names decides the verdict.
TEST(MeshDistance, LatticeBunnyUnderQuarterTurnsEqualsBruteForce) {
  tools::Mesh m = test::mesh_setup("bun_zipper_res4.ply", 16)->mesh;
  for (Vector3d& v : m.vertices) v = (v * 65536).array().round() / 65536;
  Octree A;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, A, ws);
  std::mt19937_64 rng(13);
  const int poses = test::scaled(200, 20);
  int meet = 0;
  for (int k = 0; k < poses; ++k) {
    const std::string what = "lattice pose " + std::to_string(k);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = test::ties::quarter_turn(rng);
    if (k % 2) {  // turned about corner v: R v + t = v, exactly (t is a lattice point)
      const Vector3d v = m.vertices[rng() % m.vertices.size()];
      pose.translation() = v - pose.linear() * v;
    } else {  // an offset of up to 0.25 per axis (the bunny is about 0.15 across), on the lattice
      pose.translation() = test::ties::lattice_point(rng, 1, 14) / 4;
    }
    MeshDistance got;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, got), Status::Ok) << what;
    const MeshDistance want = tools::brute_distance(m, m, pose, test::exact_triangle_distance);
    ASSERT_NEAR(got.distance, want.distance, 1e-12) << what;
    bool contact = k % 2 == 1;
    if (!contact && want.distance <= 1e-12) {
      Vector3d S[3], T[3];
      for (int c = 0; c < 3; ++c) {
        S[c] = m.vertices[m.triangles[want.triangle_a][c]];
        T[c] = pose.linear() * m.vertices[m.triangles[want.triangle_b][c]] + pose.translation();
      }
      contact = test::exact_triangle_distance(S, T) == 0;
    }
    if (contact) {
      EXPECT_TRUE(got.intersecting) << what;
      EXPECT_EQ(got.distance, 0.0) << what;
    } else {
      EXPECT_EQ(got.intersecting, want.intersecting) << what;
    }
    meet += got.intersecting;
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_LT(meet, poses);  // (and the corner-turned half meets)
  std::printf("lattice bunny poses that meet / are apart: %d / %d\n", meet, poses - meet);
}

// The octree's worst case (issue 8): one sphere inside another, about the same centre, so that
// every triangle of one is nearly as far from the other as any: exact all the same, and no
// more than a thin band of node pairs near the best distance is opened (the query stays
// bounded, far below all pairs). The benchmark times it (MeshDistance/concentric_spheres).
TEST(MeshDistance, ConcentricSpheresWorstCase) {
  const tools::Mesh outer = tools::sphere_mesh(1.0, 16), inner = tools::sphere_mesh(0.9, 16);
  Octree A, B;
  ASSERT_EQ(build_octree(outer.vertices, outer.triangles, A), Status::Ok);
  ASSERT_EQ(build_octree(inner.vertices, inner.triangles, B), Status::Ok);
  MeshWorkspace ws, tiny;
  make_workspace(A, B, ws);
  make_workspace(A, B, tiny, 2);
  std::mt19937_64 rng(5);
  const double all_pairs = double(outer.triangles.size()) * double(inner.triangles.size());
  for (int k = 0; k < test::scaled(20); ++k) {
    Eigen::Isometry3d pose = test::random_pose(rng, 0);
    pose.translation() = 1e-3 * test::random_pose(rng, 1).translation();  // nearly concentric
    MeshDistance got, small;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, got), Status::Ok);
    const MeshDistance want = tools::brute_distance(outer, inner, pose, test::exact_triangle_distance);
    ASSERT_NEAR(got.distance, want.distance, 1e-12) << "pose " << k;
    EXPECT_GT(got.distance, 0.05) << "pose " << k;
    EXPECT_LT(double(got.stats.triangle_pairs), 0.1 * all_pairs) << "pose " << k;
    // A heap of 2 pairs fills at once: the rest of the search is depth first, as exact.
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, tiny, small), Status::Ok);
    EXPECT_NEAR(small.distance, want.distance, 1e-12) << "pose " << k;
  }
}

// Found by fuzzing: a mesh of many copies of a few triangles made every leaf pair quadratic in
// the copies (17 ms for 139 triangles). Copies are listed once; the answer is unchanged.
TEST(Octree, DuplicatedTrianglesAreListedOnce) {
  tools::Mesh m;
  m.vertices = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 0}};  // vertex 4 repeats 1
  for (int k = 0; k < 300; ++k)
    m.triangles.push_back({0, 1, 2}), m.triangles.push_back({3, 4, 0}), m.triangles.push_back({2, 1, 0});
  Octree A;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A), Status::Ok);
  std::set<int> listed(A.items.begin(), A.items.end());
  EXPECT_EQ(listed, (std::set<int>{0, 1}));  // {2, 1, 0} has the corners of {0, 1, 2}
  MeshWorkspace ws;
  make_workspace(A, A, ws);
  std::mt19937_64 rng(8);
  // Brute force over the three distinct triangles (their copies are the same point sets, so
  // the same distance; 900 x 900 pairs took five minutes under the sanitizers).
  tools::Mesh distinct;
  distinct.vertices = m.vertices;
  distinct.triangles.assign(m.triangles.begin(), m.triangles.begin() + 3);
  for (int k = 0; k < 20; ++k) {
    const Eigen::Isometry3d pose = test::random_pose(rng, 1.5);
    MeshDistance got;
    ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), A, pose, ws, got), Status::Ok);
    EXPECT_NEAR(got.distance,
                tools::brute_distance(distinct, distinct, pose, test::exact_triangle_distance).distance, 1e-12)
        << "pose " << k;
    EXPECT_LE(got.stats.triangle_pairs, 4);
  }
}

// The kernel against the general exact path (Minkowski difference of the two triangles), on
// random, near-parallel, coplanar and far-from-the-origin pairs, and one in 8 tie-heavy (against
// the exact triangle distance too).
TEST(TriangleDistance, AgreesWithTheGeneralPath) {
  std::mt19937_64 rng(13);
  std::uniform_real_distribution<double> u(-1, 1), tiny(-1e-9, 1e-9);
  for (int k = 0; k < test::scaled(20000); ++k) {
    Triangle s = tools::random_triangle(rng, 1.2), t = tools::random_triangle(rng, 1.2);
    if (k % 4 == 1) {  // near-parallel: t is s's plane, lifted and tilted by ~1e-9
      const Vector3d n = (s.b - s.a).cross(s.c - s.a).normalized(), lift = 0.01 * (1 + u(rng)) * n;
      t = {s.a + lift + Vector3d(tiny(rng), tiny(rng), tiny(rng)) + 0.3 * (s.b - s.a), s.b + lift,
           s.c + lift + 0.2 * (s.a - s.c)};
    }
    if (k % 4 == 2) {  // coplanar
      const Vector3d n = (s.b - s.a).cross(s.c - s.a);
      t = {s.a + 0.7 * (s.b - s.a), s.c + (s.c - s.b) * u(rng), s.b + n.cross(s.b - s.a) * 0.5 * u(rng)};
    }
    const Vector3d far = k % 8 == 3 ? Vector3d(1e5, -1e5, 1e5) : Vector3d::Zero();
    for (Triangle* x : {&s, &t}) x->a += far, x->b += far, x->c += far;
    const bool ties = k % 8 == 7;  // tests/ties: triangles in exact contact, or on the lattice
    if (ties && k % 16 == 15)
      std::tie(s, t) = test::ties::touching_triangles(rng);
    else if (ties)
      s = test::ties::lattice_triangle(rng, 2, 1), t = test::ties::lattice_triangle(rng, 2, 1);
    // The general path (A (-) B of the two flat polytopes), not the triangle query, which is
    // built on triangle_distance.
    ConvexPolytope S, T;
    if (polytope_from_triangle(s, S) != Status::Ok || polytope_from_triangle(t, T) != Status::Ok) continue;
    Proximity want;
    ASSERT_EQ(proximity(S, T, want), Status::Ok) << "pair " << k;
    const Vector3d vs[3] = {s.a, s.b, s.c}, vt[3] = {t.a, t.b, t.c};
    Vector3d ps, pt;
    const double got = triangle_distance(vs, vt, ps, pt);
    const double tol = 1e-9 * (1 + far.norm());
    ASSERT_NEAR(got, want.distance, tol) << "pair " << k;
    ASSERT_NEAR((ps - pt).norm(), got, tol) << "pair " << k;
    if (ties) {  // and the exact distance (at contact too: the raw function may leave an ulp there)
      const double exact = test::exact_triangle_distance(vs, vt);
      ASSERT_NEAR(got, exact, 1e-15 * 8) << "lattice pair " << k;
    }
  }
}

// Found by fuzzing: triangles at 1e86 got an infinite distance (the segment test multiplies four
// coordinates). Scaling both triangles by a power of two scales the answer exactly: checked at
// 2^280 (about 1e84) and 2^-900 (about 1e-271), against the same pair near 1; the triangle
// query (its own path) gives the same distance.
TEST(TriangleDistance, HugeAndTinyCoordinates) {
  std::mt19937_64 rng(21);
  for (int k = 0; k < test::scaled(2000); ++k) {
    const Triangle a = tools::random_triangle(rng, 1.2), b = tools::random_triangle(rng, 1.2);
    const Vector3d s[3] = {a.a, a.b, a.c}, t[3] = {b.a, b.b, b.c};
    Vector3d p, q;
    const double d = triangle_distance(s, t, p, q);
    for (int e : {280, -900}) {
      const double f = std::ldexp(1.0, e);
      const Vector3d fs[3] = {f * s[0], f * s[1], f * s[2]}, ft[3] = {f * t[0], f * t[1], f * t[2]};
      Vector3d fp, fq;
      ASSERT_NEAR(triangle_distance(fs, ft, fp, fq) / f, d, 1e-12 * (1 + d)) << "pair " << k << " scale 2^" << e;
      EXPECT_NEAR((fp - fq).stableNorm() / f, d, 1e-12 * (1 + d));  // norm() underflows at 2^-900
      Proximity prox;
      ASSERT_EQ(proximity(Triangle{fs[0], fs[1], fs[2]}, Triangle{ft[0], ft[1], ft[2]}, prox), Status::Ok);
      ASSERT_NEAR(prox.distance / f, d, 1e-12 * (1 + d)) << "pair " << k << " scale 2^" << e;
    }
  }
  // Subnormal spans (a fuzz finding: 2^-exponent overflowed to inf and the distance was NaN).
  const double tiny = 3e-309;
  const Vector3d point[3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const Vector3d off[3] = {{tiny, 0, 0}, {tiny, 1e-310, 0}, {tiny, 0, 1e-310}};
  const Vector3d touching[3] = {{0, 0, 0}, {1.3906711615669959e-309, 0, 0}, {0, 0, 0}};
  Vector3d p, q;
  EXPECT_DOUBLE_EQ(triangle_distance(point, off, p, q), tiny);
  EXPECT_EQ(triangle_distance(point, touching, p, q), 0);
}

TEST(TriangleDistance, DegenerateTriangles) {
  const Vector3d seg[3] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};    // collinear
  const Vector3d point[3] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};  // one point
  const Vector3d tri[3] = {{3, 0, -1}, {3, 0, 1}, {3, 1, 0}};
  Vector3d p, q;
  EXPECT_NEAR(triangle_distance(seg, point, p, q), 1, 1e-15);
  EXPECT_NEAR(triangle_distance(seg, tri, p, q), 1, 1e-15);
  EXPECT_NEAR(triangle_distance(point, tri, p, q), 3, 1e-15);  // onto the corner (3, 1, 0)
  // A flat triangle whose rounded normal is not zero, through the other's interior (found by
  // the batched kernel's test: this path reported 0.156, taking the noise normal as a
  // separating plane). Where its line crosses the other's plane, the crossing is inside.
  const Vector3d a(0.39706835965566656, -0.37874288836664127, -0.16360182120071276),
      b(0.69917564238213692, 0.38752137874385473, -0.89811582873594342);
  const Vector3d thin[3] = {a, b, a + 0.5 * (b - a)};
  const Vector3d other[3] = {{-0.21181114053935213, 0.046572801986883627, 0.035790152041531798},
                             {0.95607882776826059, -0.15778320336505658, -0.40568363894261927},
                             {-0.23479936340708651, -0.37508253016353221, -0.90307042131578441}};
  const Vector3d n = (other[1] - other[0]).cross(other[2] - other[0]);
  const double ha = n.dot(a - other[0]), hb = n.dot(b - other[0]);
  ASSERT_LT(ha * hb, 0);  // a and b on either side of the plane
  const Vector3d x = a + ha / (ha - hb) * (b - a);
  for (int k = 0; k < 3; ++k) ASSERT_GT((other[(k + 1) % 3] - other[k]).cross(x - other[k]).dot(n), 0);
  EXPECT_EQ(triangle_distance(thin, other, p, q), 0);
  EXPECT_LE((p - x).norm(), 1e-15);
}

// A vertex lying in a sliver 700 long and 0.06 wide (a fuzz finding: the barycentric region
// tests cancelled and put it 9.3e-7 away). The sliver is in the plane x = y, which holds the
// vertex, and at the vertex's height along the sliver it spans z in [120.457, 120.502].
TEST(TriangleDistance, VertexInsideASliver) {
  const Vector3d s[3] = {{465.8125, 124.46875, 120.46875}, {120.46875, 120.46875, 120.46875}, {12, 0, 0}};
  const Vector3d t[3] = {{405.578125, 405.578125, 405.578125}, {0, 0, 0.046875}, {0, 0, -0.015625}};
  Vector3d p, q;
  EXPECT_LE(triangle_distance(s, t, p, q), 1e-13);
  EXPECT_LE((p - s[1]).norm(), 1e-12);
}

TEST(Octree, RejectsBadMeshes) {
  Octree o;
  const std::vector<Vector3d> v = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  EXPECT_EQ(build_octree(v, {}, o), Status::EmptyMesh);  // (3 points and no triangle: no mesh, and it says so)
  EXPECT_EQ(build_octree(v, {{0, 1, 3}}, o), Status::InvalidMesh);
  EXPECT_EQ(build_octree(v, {{0, -1, 2}}, o), Status::InvalidMesh);
  auto bad = v;
  bad[1].y() = std::nan("");
  EXPECT_EQ(build_octree(bad, {{0, 1, 2}}, o), Status::NonFinite);
  bad[1].y() = std::numeric_limits<double>::infinity();
  EXPECT_EQ(build_octree(bad, {{0, 1, 2}}, o), Status::NonFinite);
  bad[1].y() = -1e101;
  EXPECT_EQ(build_octree(bad, {{0, 1, 2}}, o), Status::OutOfRange);
  OctreeOptions options;
  options.leaf_size = 0;
  EXPECT_EQ(build_octree(v, {{0, 1, 2}}, o, options), Status::InvalidArgument);  // (the option, not the mesh)
  options.leaf_size = 1, options.max_depth = 25;
  EXPECT_EQ(build_octree(v, {{0, 1, 2}}, o, options), Status::InvalidArgument);
  // A mesh under kMinExtent in both its size and its place (products underflow) is out of
  // range; a single point (size 0) is not.
  EXPECT_EQ(build_octree(tools::scaled(v, 1e-101), {{0, 1, 2}}, o), Status::OutOfRange);
  EXPECT_EQ(build_octree(std::vector<Vector3d>{Vector3d(0, 0, 0)}, o), Status::Ok);
  EXPECT_EQ(build_octree(std::vector<Vector3d>{Vector3d(0, 0, 5.7e-101)}, o), Status::Ok);  // (Hypothesis found it refused)
  // Unused vertices and degenerate triangles are fine.
  auto extra = v;
  extra.emplace_back(5, 5, 5);
  EXPECT_EQ(build_octree(extra, {{0, 1, 2}, {0, 0, 1}}, o), Status::Ok);
}

// Scaling the scene by 2^k is exact, so every answer scales with it (times stay): mesh-mesh
// and mesh-shape distances, contact depths and areas, and sweeps, from 2^-330 to 2^330 (about
// kMinExtent to kMaxCoordinate), against the answers at scale 1 (brute force checks those
// elsewhere). Before: contact depth 0 from 2^260 (a cross product's squared norm overflowed,
// so normals and areas vanished), and sweeps hit at once under 2^-80 (the octree's margins
// were 1e-15 and 1e-12 absolute).
TEST(MeshQueries, ScaleWithTheSceneByPowersOfTwo) {
  const tools::Mesh sphere = tools::sphere_mesh(1.0, 6);
  struct Answers {
    double mesh, shape[3], depth[3], area[3], time[3];
  };
  const auto answers = [&](double s) {
    Answers x{};
    std::vector<Vector3d> v = tools::scaled(sphere.vertices, s);
    Octree T;
    EXPECT_EQ(build_octree(v, sphere.triangles, T), Status::Ok);
    MeshWorkspace ws;
    make_workspace(T, T, ws);
    Box b;
    b.half_extents = Vector3d(0.3, 0.2, 0.25) * s;
    ConvexShape tools_[3];
    shape_from_box(b, tools_[0]), shape_with_radius(tools_[0], 0.1 * s, tools_[1]), shape_from_sphere(0.4 * s, tools_[2]);
    Eigen::Isometry3d far = Eigen::Isometry3d::Identity(), near;
    far.linear() = tools::axis_angle(Vector3d(1, 2, 3), 0.3), near = far;
    far.translation() = Vector3d(2.5, -0.9, 0.7) * s, near.translation() = Vector3d(0.9, 0.2, 0.1) * s;
    const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
    MeshDistance d;
    EXPECT_EQ(mesh_distance(T, I, T, far, ws, d), Status::Ok);
    x.mesh = d.distance / s;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(mesh_distance(T, I, tools_[k], far, d), Status::Ok);
      MeshContact c;
      EXPECT_EQ(mesh_contact(T, I, tools_[k], near, ws, c), Status::Ok);
      TimeOfImpact t;
      EXPECT_EQ(time_of_impact(T, I, tools_[k], far, near, t), Status::Ok);
      x.shape[k] = d.distance / s, x.depth[k] = c.penetration_depth / s, x.area[k] = c.area / s / s, x.time[k] = t.time;
    }
    return x;
  };
  const Answers one = answers(1);
  EXPECT_GT(one.mesh, 0);
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(one.depth[k] > 0 && one.time[k] > 0 && one.time[k] < 1) << k;
  for (int e : {-330, -200, -80, 80, 200, 260, 330}) {
    const Answers x = answers(std::ldexp(1.0, e));
    const auto same = [](double p, double q) { return std::abs(p - q) <= 1e-12 * (1 + std::abs(q)); };
    EXPECT_TRUE(same(x.mesh, one.mesh)) << "2^" << e << ": mesh distance " << x.mesh << " for " << one.mesh;
    for (int k = 0; k < 3; ++k) {
      EXPECT_TRUE(same(x.shape[k], one.shape[k])) << "2^" << e << " tool " << k << ": distance " << x.shape[k];
      EXPECT_TRUE(same(x.depth[k], one.depth[k])) << "2^" << e << " tool " << k << ": depth " << x.depth[k];
      EXPECT_TRUE(same(x.area[k], one.area[k])) << "2^" << e << " tool " << k << ": area " << x.area[k];
      EXPECT_TRUE(same(x.time[k], one.time[k])) << "2^" << e << " tool " << k << ": time " << x.time[k];
    }
  }
}

TEST(Octree, RejectsABadPoseAndAForeignWorkspace) {
  const tools::Mesh m = test::test_mesh("bun_zipper_res4.ply", 16);
  Octree A, small;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A), Status::Ok);
  ASSERT_EQ(build_octree({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, small), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, A, ws);
  MeshDistance d;
  // Either pose, not rigid or not finite: InvalidPose, as every other query says.
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d stretched = identity, nan = identity;
  stretched.linear()(0, 0) = 2;
  nan.translation().x() = std::nan("");
  for (const Eigen::Isometry3d& bad : {stretched, nan}) {
    EXPECT_EQ(mesh_distance(A, identity, A, bad, ws, d), Status::InvalidPose);
    EXPECT_EQ(mesh_distance(A, bad, A, identity, ws, d), Status::InvalidPose);
  }
  EXPECT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), small, Eigen::Isometry3d::Identity(), ws, d),
            Status::WorkspaceMismatch);  // (made for A and A: the meshes are fine)
  // A workspace make_workspace never sized is refused; a copy of a sized one works.
  MeshWorkspace empty;
  EXPECT_EQ(mesh_distance(A, identity, A, identity, empty, d), Status::WorkspaceMismatch);
  MeshWorkspace copy = ws;
  EXPECT_EQ(mesh_distance(A, identity, A, identity, copy, d), Status::Ok);
  EXPECT_TRUE(d.intersecting);
}

// mesh_contact of a box tool, prepared once and posed per call, on a flat floor (z = 0, wound
// counter-clockwise from +z): turned about z and by quarter turns about x, so that its lowest
// face stays level and the push-out is straight up by (half height - centre height), a figure
// computed here from the box, not by the library; the contact's area and centre are the box's
// level section's. Bad poses and empty tools get a status.
TEST(MeshContact, PosedBoxOnAFloorIsPushedStraightUp) {
  const std::vector<Vector3d> floor{{-5, -5, 0}, {5, -5, 0}, {5, 5, 0}, {-5, 5, 0}};
  Octree A;
  ASSERT_EQ(build_octree(floor, {{0, 1, 2}, {0, 2, 3}}, A), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, A, ws);
  Box box;
  box.half_extents = Vector3d(0.3, 0.2, 0.1);
  ConvexShape tool;
  ASSERT_EQ(shape_from_box(box, tool), Status::Ok);
  std::mt19937_64 rng(41), world_rng(42);
  std::uniform_real_distribution<double> u(-1, 1);
  int touching = 0;
  for (int k = 0; k < 200; ++k) {
    SCOPED_TRACE("pose " + std::to_string(k));
    const int quarter = k % 4;  // 0, 2: z half extent is vertical; 1, 3: y's
    const double half_height = quarter % 2 ? box.half_extents.y() : box.half_extents.z();
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() =
        (Eigen::AngleAxisd(M_PI * u(rng), Vector3d::UnitZ()) * Eigen::AngleAxisd(M_PI / 2 * quarter, Vector3d::UnitX()))
            .toRotationMatrix();
    pose.translation() = Vector3d(3 * u(rng), 3 * u(rng), 1.5 * half_height * u(rng) + 0.5 * half_height);
    MeshContact c;
    ASSERT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), tool, pose, ws, c), Status::Ok);
    const double want = half_height - pose.translation().z();  // the bottom face's depth below z = 0
    ASSERT_EQ(c.intersecting, want > 1e-12);  // the centre is above -half_height: the floor cuts the box
    if (!c.intersecting) continue;
    ++touching;
    EXPECT_NEAR(c.penetration_depth, want, 1e-12);
    EXPECT_NEAR((c.penetration_direction - Vector3d::UnitZ()).norm(), 0, 1e-12);
    EXPECT_NEAR(c.point.z(), 0, 1e-12);
    // The part inside is the box's level section, a rectangle of its two horizontal extents
    // about the point under its centre: the area and centre that force and torque act by.
    const double width = quarter % 2 ? box.half_extents.z() : box.half_extents.y();
    EXPECT_NEAR(c.area, 4 * box.half_extents.x() * width, 1e-12);
    EXPECT_NEAR((c.centre - Vector3d(pose.translation().x(), pose.translation().y(), 0)).norm(), 0, 1e-12);
    // Floor and tool moved together by one rigid motion W (world poses): the same contact,
    // its point and direction moved by W.
    const Eigen::Isometry3d W = test::random_pose(world_rng, 1.0);
    MeshContact moved;
    ASSERT_EQ(mesh_contact(A, W, tool, W * pose, ws, moved), Status::Ok);
    ASSERT_TRUE(moved.intersecting);
    EXPECT_NEAR(moved.penetration_depth, want, 1e-12);
    EXPECT_NEAR((moved.penetration_direction - W.linear() * Vector3d::UnitZ()).norm(), 0, 1e-12);
    EXPECT_NEAR((W.inverse() * moved.point).z(), 0, 1e-12);
    EXPECT_NEAR((moved.centre - W * c.centre).norm(), 0, 1e-12);
  }
  EXPECT_GT(touching, 50);
  MeshContact c;
  Eigen::Isometry3d scaled = Eigen::Isometry3d::Identity();
  scaled.linear() *= 1.01;
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), tool, scaled, ws, c), Status::InvalidPose);
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), ConvexShape{}, Eigen::Isometry3d::Identity(), ws, c),
            Status::TooFewPoints);
  EXPECT_EQ(mesh_contact(A, scaled, tool, Eigen::Isometry3d::Identity(), ws, c), Status::InvalidPose);
  MeshWorkspace none;
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), tool, Eigen::Isometry3d::Identity(), none, c),
            Status::WorkspaceMismatch);
  EXPECT_FALSE(c.intersecting);
  // Past the fixed scratch (kMaxToolVertices), with a radius or not: the capacity, as
  // mesh_distance says. A flat tool has no inside to clip by; with a radius it has.
  ConvexShape many, rounded_many, flat, swept;
  ASSERT_EQ(shape_from_points(tools::sphere_mesh(0.1, 20).vertices, many), Status::Ok);
  ASSERT_GT(many.polytope().vertices.size(), size_t(kMaxToolVertices));
  ASSERT_EQ(shape_with_radius(many, 0.01, rounded_many), Status::Ok);
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), many, Eigen::Isometry3d::Identity(), ws, c),
            Status::CapacityExceeded);
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), rounded_many, Eigen::Isometry3d::Identity(), ws, c),
            Status::CapacityExceeded);
  ASSERT_EQ(shape_from_triangle({Eigen::Vector3d(0, 0, 0.05), Eigen::Vector3d(1, 0, 0.05), Eigen::Vector3d(0, 1, 0.05)}, flat),
            Status::Ok);
  EXPECT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), flat, Eigen::Isometry3d::Identity(), ws, c), Status::InvalidMesh);
  ASSERT_EQ(shape_with_radius(flat, 0.125, swept), Status::Ok);
  ASSERT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), swept, Eigen::Isometry3d::Identity(), ws, c), Status::Ok);
  EXPECT_TRUE(c.intersecting);
}

// mesh_contact of a tool of many faces (a 64-sided prism: its faces are climbed across their
// edges to reject a triangle) standing on a finely tessellated floor (z = 0), pressed h in:
// the parts inside are the prism's section, a regular 64-gon about its axis, whose area
// (n R^2 sin(2 pi / n) / 2) and centre are computed here; it is pushed straight up by h.
TEST(MeshContact, ManyFacedPrismOnAFloorIsItsSection) {
  const tools::Mesh floor = tools::box_mesh(Vector3d(-5, -5, -1), Vector3d(5, 5, 0), 40);
  Octree A;
  ASSERT_EQ(build_octree(floor.vertices, floor.triangles, A), Status::Ok);
  MeshWorkspace ws;
  make_workspace(A, A, ws);
  constexpr int n = 64;
  std::vector<Vector3d> corners;
  for (int k = 0; k < n; ++k)
    for (double z : {-1.0, 1.0}) corners.emplace_back(std::cos(2 * M_PI * k / n), std::sin(2 * M_PI * k / n), z);
  ConvexShape prism;
  ASSERT_EQ(shape_from_points(corners, prism), Status::Ok);
  ASSERT_EQ(prism.polytope().faces.size(), size_t(n + 2));
  const double area = n * std::sin(2 * M_PI / n) / 2;
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int k = 0; k < 50; ++k) {
    SCOPED_TRACE("pose " + std::to_string(k));
    const double h = 0.05 + 0.9 * (u(rng) + 1) / 2;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(M_PI * u(rng), Vector3d::UnitZ()).toRotationMatrix();
    pose.translation() = Vector3d(3 * u(rng), 3 * u(rng), 1 - h);
    MeshContact c;
    ASSERT_EQ(mesh_contact(A, Eigen::Isometry3d::Identity(), prism, pose, ws, c), Status::Ok);
    ASSERT_TRUE(c.intersecting);
    EXPECT_NEAR(c.area, area, 1e-9);
    EXPECT_NEAR((c.centre - Vector3d(pose.translation().x(), pose.translation().y(), 0)).norm(), 0, 1e-9);
    EXPECT_NEAR(c.penetration_depth, h, 1e-9);
    EXPECT_NEAR((c.penetration_direction - Vector3d::UnitZ()).norm(), 0, 1e-9);
  }
}

// Every triangle is listed in every leaf whose cube it meets: checked against the exact
// box-triangle proximity of the general path, for every (leaf, triangle) pair of a small mesh.
// Every triangle is listed in exactly one leaf (copies of an earlier one in none), and its
// corners lie in the box and the slab of that leaf and of every node above it: the bounds the
// search prunes with.
TEST(Octree, EveryTriangleOnceInsideItsNodesBounds) {
  const tools::Mesh m = test::test_mesh("bun_zipper_res3.ply", 24);
  Octree A;
  OctreeOptions options;
  options.leaf_size = 8;  // a deep tree
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A, options), Status::Ok);
  std::vector<bool> copy(m.triangles.size());
  std::set<std::array<double, 9>> seen;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    std::array<std::array<double, 3>, 3> c;
    for (int k = 0; k < 3; ++k)
      c[k] = {m.vertices[m.triangles[t][k]].x(), m.vertices[m.triangles[t][k]].y(), m.vertices[m.triangles[t][k]].z()};
    std::sort(c.begin(), c.end());
    copy[t] = !seen.insert({c[0][0], c[0][1], c[0][2], c[1][0], c[1][1], c[1][2], c[2][0], c[2][1], c[2][2]}).second;
  }
  std::vector<int> parent(A.nodes.size(), -1), times(m.triangles.size(), 0);
  for (size_t i = 0; i < A.nodes.size(); ++i)
    for (int c = A.nodes[i].first_child; c >= 0 && c < A.nodes[i].first_child + A.nodes[i].child_count; ++c)
      parent[size_t(c)] = int(i);
  int checked = 0;
  for (size_t i = 0; i < A.nodes.size(); ++i) {
    if (A.nodes[i].first_child >= 0) continue;
    for (int x = A.nodes[i].first; x < A.nodes[i].first + A.nodes[i].count; ++x) {
      const int t = A.items[size_t(x)];
      ++times[size_t(t)];
      for (int n = int(i); n >= 0; n = parent[size_t(n)], ++checked) {
        const Octree::Node& node = A.nodes[size_t(n)];
        for (int k : m.triangles[size_t(t)]) {
          const Vector3d& v = m.vertices[size_t(k)];
          ASSERT_LE(((v - node.box_center).cwiseAbs() - node.box_half).maxCoeff(), 0.0)
              << "triangle " << t << " node " << n;
          ASSERT_GE(node.normal.dot(v), node.slab_lo) << "triangle " << t << " node " << n;
          ASSERT_LE(node.normal.dot(v), node.slab_hi) << "triangle " << t << " node " << n;
        }
      }
    }
  }
  for (size_t t = 0; t < m.triangles.size(); ++t) ASSERT_EQ(times[t], copy[t] ? 0 : 1) << "triangle " << t;
  EXPECT_GT(A.depth, 3);
  EXPECT_GT(checked, 10000);
}

// A node holding both sheets of a thin shell gets a slab within 4 times the shell's thickness:
// the sheets' oriented normals cancel (the mean normal of a closed surface is zero), so the slab
// takes the axis of their unoriented normals. The lens is tilted off the axes, where the boxes
// do not fit it either. With the mean normal alone (stop 50) the root's slab was 0.51 wide, and
// 155 of the 492 nodes were wider than 4 times the shell.
TEST(Octree, SlabsOfAThinShellAreAsThinAsTheShell) {
  const tools::Mesh m = tools::tilted(tools::flattened_mesh(20));  // 0.005 thick
  Octree A;
  OctreeOptions options;
  options.leaf_size = 8;
  ASSERT_EQ(build_octree(m.vertices, m.triangles, A, options), Status::Ok);
  ASSERT_GT(A.depth, 2);
  for (size_t i = 0; i < A.nodes.size(); ++i)
    ASSERT_LE(A.nodes[i].slab_hi - A.nodes[i].slab_lo, 0.02 * (1 + 1e-9)) << "node " << i << " of " << A.nodes.size();
  const Vector3d axis = tools::tilt() * Vector3d::UnitZ();  // the lens's axis
  EXPECT_NEAR(std::abs(A.nodes[0].normal.dot(axis)), 1.0, 1e-9);  // the root holds both sheets whole
  EXPECT_LE(A.nodes[0].slab_hi - A.nodes[0].slab_lo, 0.005 * (1 + 1e-9));
}

}  // namespace
}  // namespace minksum
