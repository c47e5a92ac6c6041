// Exact contact on every query kind (tests/ties: lattice boxes face on face, a triangle's corner
// on a box's face or lying in its plane, triangles sharing a corner, an edge point or a face
// point): the verdict is intersecting and the distance exactly 0, for the single queries, the
// polytopes and the posed shapes (cold and coherent), and the batched kernels.
#include <gtest/gtest.h>

#include <set>
#include <minksum/kernels.hpp>
#include <minksum/minksum.hpp>

#include "checks.hpp"
#include "exact_distance.hpp"
#include "ties.hpp"

#include <array>
#include <limits>

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
  expect_contact(proximity(SA, m, SB, m, p, Want::Patch), p, what + " as shapes");
  expect_contact(proximity(SA, m, SB, m, cache, p, Want::Patch), p, what + " as shapes, coherent");
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


// Brute force on lattice operands: the least exact distance between their surfaces (the
// distance when apart; 0 when the surfaces meet) and whether a corner of one lies in the other
// box (then they overlap although the surfaces may not meet).
double exact_gap(const Box& a, const Box& b) {
  ConvexPolytope A, B;
  polytope_from_box(a, A), polytope_from_box(b, B);
  return test::ties::exact_surface_gap(A, B);
}
double exact_gap(const Box& a, const Triangle& t) {
  ConvexPolytope A, B;
  polytope_from_box(a, A), polytope_from_triangle(t, B);
  return test::ties::exact_surface_gap(A, B);
}
double exact_gap(const Triangle& s, const Triangle& t) {
  ConvexPolytope A, B;
  polytope_from_triangle(s, A), polytope_from_triangle(t, B);
  return test::ties::exact_surface_gap(A, B);
}
bool inside(const Box& box, const Vector3d& x) {
  return ((box.rotation.transpose() * (x - box.center)).cwiseAbs() - box.half_extents).maxCoeff() <= 0;
}

// Random lattice operands (quarter-turned boxes and triangles, 1/8 steps within +-4), which
// tie everywhere (parallel faces and edges, shared planes) and often touch: every query kind
// against brute force with the exact triangle distance; the verdict must be exact (a lattice
// pair meets or is at least 1/8^2 / size apart).
TEST(Ties, LatticeQueriesEqualTheExactDistance) {
  std::mt19937_64 rng(31);
  const int n = test::scaled(200);
  int meet[3] = {0, 0, 0}, apart[3] = {0, 0, 0};
  for (int k = 0; k < n; ++k) {
    const Box a = test::ties::lattice_box(rng, 3, 3), b = test::ties::lattice_box(rng, 3, 3);
    const Triangle s = test::ties::lattice_triangle(rng, 4, 3), t = test::ties::lattice_triangle(rng, 4, 3);
    const auto ca = test::ties::corners(a), cb = test::ties::corners(b), cs = test::ties::corners(s),
               ct = test::ties::corners(t);
    struct Case {
      const char* name;
      Status status = Status::Ok;
      Proximity p;
      double exact = 0;
      bool contained = false;
    } cases[3];
    cases[0].name = "box-box", cases[0].status = proximity(a, b, cases[0].p), cases[0].exact = exact_gap(a, b);
    for (const auto& x : cb) cases[0].contained = cases[0].contained || inside(a, x);
    for (const auto& x : ca) cases[0].contained = cases[0].contained || inside(b, x);
    cases[1].name = "box-triangle", cases[1].status = proximity(a, s, cases[1].p), cases[1].exact = exact_gap(a, s);
    cases[1].contained = inside(a, s.a);
    cases[2].name = "triangle-triangle", cases[2].status = proximity(s, t, cases[2].p),
    cases[2].exact = exact_gap(s, t);
    for (int j = 0; j < 3; ++j) {
      const Case& c = cases[j];
      const std::string what = std::string(c.name) + " case " + std::to_string(k);
      ASSERT_EQ(c.status, Status::Ok) << what;
      const bool overlap = c.exact == 0 || c.contained;
      EXPECT_EQ(c.p.intersecting, overlap) << what << ": exact distance " << c.exact;
      EXPECT_NEAR(c.p.distance, overlap ? 0.0 : c.exact, 64 * std::numeric_limits<double>::epsilon() * 8) << what;
      if (overlap) EXPECT_EQ(c.p.distance, 0.0) << what;
      ++(overlap ? meet : apart)[j];
    }
    // The box pair as posed shapes under one exact motion: the same answer.
    ConvexShape SA, SB;
    ASSERT_EQ(shape_from_box(a, SA), Status::Ok);
    ASSERT_EQ(shape_from_box(b, SB), Status::Ok);
    Proximity p;
    const Eigen::Isometry3d m = lattice_motion(rng);
    ASSERT_EQ(proximity(SA, m, SB, m, p, Want::Patch), Status::Ok);
    EXPECT_EQ(p.intersecting, cases[0].p.intersecting) << "shapes case " << k;
    EXPECT_NEAR(p.distance, cases[0].p.distance, 64 * std::numeric_limits<double>::epsilon() * 16)
        << "shapes case " << k;
    if (testing::Test::HasFailure()) return;
  }
  std::printf("lattice pairs that meet / are apart: box-box %d / %d, box-triangle %d / %d, triangle-triangle %d / %d\n",
              meet[0], apart[0], meet[1], apart[1], meet[2], apart[2]);
  for (int j = 0; j < 3; ++j) {  // both verdicts were tested, in every kind
    EXPECT_GT(meet[j], n / 20) << j;
    EXPECT_GT(apart[j], n / 20) << j;
  }
}


// "Meshes" of lattice triangles (a soup: the octree does not need a closed surface), 30 each,
// under lattice motions (quarter turns, 1/8 steps) that keep every coordinate exact: the
// octree's distance against the least exact distance over all triangle pairs, and its verdict
// against exact contact. Ties everywhere: shared planes, parallel edges, touching pairs.
TEST(Ties, OctreeOnLatticeTrianglesEqualsTheExactDistance) {
  std::mt19937_64 rng(47);
  const auto soup = [&](int n) {
    std::vector<Vector3d> v;
    std::vector<std::array<int, 3>> t;
    for (int k = 0; k < n; ++k) {
      const Triangle x = test::ties::lattice_triangle(rng, 2, 3);
      for (const Vector3d& p : {x.a, x.b, x.c}) v.push_back(p);
      t.push_back({3 * k, 3 * k + 1, 3 * k + 2});
    }
    return std::make_pair(v, t);
  };
  int meet = 0, apart = 0;
  for (int round = 0; round < test::scaled(12, 4); ++round) {
    const auto [va, ta] = soup(30);
    const auto [vb, tb] = soup(30);
    Octree A, B;
    ASSERT_EQ(build_octree(va, ta, A), Status::Ok);
    ASSERT_EQ(build_octree(vb, tb, B), Status::Ok);
    MeshWorkspace ws;
    make_workspace(A, B, ws);
    for (int k = 0; k < 4; ++k) {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.linear() = test::ties::quarter_turn(rng);
      pose.translation() = test::ties::lattice_point(rng, 1 + 2 * k, 3);  // from overlapping to apart
      MeshDistance got;
      ASSERT_EQ(mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, got), Status::Ok);
      // Every pair, skipped only when bounding spheres (about a corner, with a margin far
      // above rounding) are already farther apart than the best exact distance.
      double exact = std::numeric_limits<double>::infinity();
      for (const auto& x : ta)
        for (const auto& y : tb) {
          if (exact == 0) break;  // (nothing is nearer)
          const Vector3d S[3] = {va[x[0]], va[x[1]], va[x[2]]};
          const Vector3d T[3] = {pose.linear() * vb[y[0]] + pose.translation(),
                                 pose.linear() * vb[y[1]] + pose.translation(),
                                 pose.linear() * vb[y[2]] + pose.translation()};
          const double rs = std::max((S[1] - S[0]).norm(), (S[2] - S[0]).norm()),
                       rt = std::max((T[1] - T[0]).norm(), (T[2] - T[0]).norm());
          if ((S[0] - T[0]).norm() - rs - rt > exact + 1e-9) continue;
          exact = std::min(exact, test::exact_triangle_distance(S, T));
        }
      const std::string what = "round " + std::to_string(round) + " pose " + std::to_string(k);
      EXPECT_EQ(got.intersecting, exact == 0) << what << ": exact " << exact;
      EXPECT_NEAR(got.distance, exact, 64 * std::numeric_limits<double>::epsilon() * 16) << what;
      if (exact == 0) EXPECT_EQ(got.distance, 0.0) << what;
      ++(exact == 0 ? meet : apart);
    }
    if (testing::Test::HasFailure()) return;
  }
  EXPECT_GT(meet, 0);
  EXPECT_GT(apart, 0);
  std::printf("lattice soups that meet / are apart: %d / %d\n", meet, apart);
}


// ties::quarter_turn draws every one of the 24 rotations of the cube (the header's promise; it
// gave 14 before), each a proper rotation with entries in {-1, 0, 1}.
TEST(Ties, QuarterTurnGivesAll24Rotations) {
  std::mt19937_64 rng(24);
  std::set<std::vector<int>> seen;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Matrix3d r = test::ties::quarter_turn(rng);
    EXPECT_TRUE((r * r.transpose()).isIdentity(0)) << r;
    EXPECT_EQ(r.determinant(), 1) << r;
    seen.insert(std::vector<int>(r.data(), r.data() + 9));
  }
  EXPECT_EQ(seen.size(), 24u);
}

}  // namespace
}  // namespace minksum
