// Building polytopes: from points (the exact hull), explicit meshes, boxes and triangles; bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <minksum/minksum.hpp>

#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

// Structural invariants every polytope must satisfy, checked from the raw arrays.
void expect_valid(const ConvexPolytope& p) {
  const int V = int(p.vertices.size()), E = int(p.edges.size()), F = int(p.faces.size());
  if (!p.flat) EXPECT_EQ(V - E + F, 2);
  for (const auto& f : p.faces) {
    EXPECT_NEAR(f.normal.norm(), 1.0, 1e-12);
    Vector3d newell = Vector3d::Zero();
    for (size_t k = 0; k < f.loop.size(); ++k) {
      const Vector3d& a = p.vertices[f.loop[k]];
      newell += a.cross(p.vertices[f.loop[(k + 1) % f.loop.size()]]);
      EXPECT_NEAR(f.normal.dot(a), f.offset, 1e-9);
    }
    EXPECT_GT(newell.dot(f.normal), 0) << "loop not counter-clockwise from outside";
    for (const auto& v : p.vertices) EXPECT_LE(f.normal.dot(v), f.offset + 1e-9);
  }
  for (const auto& e : p.edges) {
    auto has = [&](int face, int a, int b) {
      const auto& l = p.faces[face].loop;
      for (size_t k = 0; k < l.size(); ++k)
        if (l[k] == a && l[(k + 1) % l.size()] == b) return true;
      return false;
    };
    EXPECT_TRUE(has(e.left, e.v0, e.v1));
    EXPECT_TRUE(has(e.right, e.v1, e.v0));
  }
}

TEST(Polytope, CubeFromPointsHasSixQuadFaces) {
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(tools::cube_points(), p), Status::Ok);
  EXPECT_EQ(p.vertices.size(), 8u);
  EXPECT_EQ(p.faces.size(), 6u);  // coplanar triangles merged into quads
  EXPECT_EQ(p.edges.size(), 12u);
  for (const auto& f : p.faces) EXPECT_EQ(f.loop.size(), 4u);
  expect_valid(p);
}

TEST(Polytope, PlatonicSolidsHaveTheirKnownCounts) {
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(tools::icosahedron_points(), p), Status::Ok);
  EXPECT_EQ(p.faces.size(), 20u);
  EXPECT_EQ(p.edges.size(), 30u);
  expect_valid(p);
  // (The pyritohedron of integer coordinates: a regular dodecahedron's rounded corners are not
  // coplanar, and their exact hull has triangles.)
  ASSERT_EQ(polytope_from_points(tools::exact_dodecahedron_points(), p), Status::Ok);
  EXPECT_EQ(p.faces.size(), 12u);
  EXPECT_EQ(p.vertices.size(), 20u);
  expect_valid(p);
}

TEST(Polytope, InteriorAndDuplicatePointsAreDroppedAndIndicesKept) {
  auto pts = tools::cube_points();
  pts.insert(pts.begin(), Vector3d(0.1, 0.2, 0.3));  // interior
  pts.push_back(pts[5]);                             // duplicate of input point 5
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(pts, p), Status::Ok);
  EXPECT_EQ(p.vertices.size(), 8u);
  for (size_t k = 0; k < p.vertices.size(); ++k) {
    EXPECT_EQ(p.vertices[k], pts[p.input_index[k]]);
    EXPECT_NE(p.input_index[k], 0);
    EXPECT_NE(p.input_index[k], 9) << "the first of two duplicates is kept";
  }
}

TEST(Polytope, CoplanarPointsGiveAFlatPolytopeWithTwoSides) {
  const std::vector<Vector3d> pts = {{0, 0, 1}, {2, 0, 1}, {2, 1, 1}, {0, 1, 1}, {1, 0.5, 1}, {1, 0, 1}};
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(pts, p), Status::Ok);
  EXPECT_TRUE(p.flat);
  EXPECT_EQ(p.vertices.size(), 4u);  // interior point and the point on an edge are dropped
  ASSERT_EQ(p.faces.size(), 2u);
  EXPECT_NEAR(std::abs(p.faces[0].normal.z()), 1.0, 1e-15);
  EXPECT_EQ(p.faces[0].normal, -p.faces[1].normal);
  EXPECT_EQ(p.edges.size(), 4u);
  expect_valid(p);
}

// The Hypothesis campaign of caba389 (seed 1207004): two points 1.2e-7 apart, a third 1000
// away and a fourth 1 off their line. Flat to 1e-10 (the second point 5.8e-11 of the diagonal
// off the others' plane), and the planar hull dropped the far corner: its triangle with the two
// near points has an area of 3e-19, under an area tolerance. "Collinear" for a triangle 1000
// long and 1 wide. The points span a volume: every one is a corner of their hull.
TEST(Polytope, NearlyCoincidentPointsBesideFarCornersAreNotCollinear) {
  const std::vector<Vector3d> pts = {{0, 0, 0}, {0, -0x1p-23, 0}, {0, -0x1p-24, 1000}, {1, 0, -193}};
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(pts, p), Status::Ok);
  EXPECT_FALSE(p.flat);
  ASSERT_EQ(p.vertices.size(), 4u);
  expect_valid(p);
  // The same corners exactly in a plane (x = 0): a flat polygon, the far corners on it.
  const std::vector<Vector3d> flat = {{0, 0, 0}, {0, -0x1p-23, 0}, {0, -0x1p-24, 1000}, {0, 1, -193}};
  ASSERT_EQ(polytope_from_points(flat, p), Status::Ok);
  EXPECT_TRUE(p.flat);
  for (const int far : {2, 3})
    EXPECT_NE(std::find(p.input_index.begin(), p.input_index.end(), far), p.input_index.end()) << far;
  expect_valid(p);
}

// A polygon exactly in a tilted plane keeps a corner that lies 1e-14 of its size off the line
// through its neighbours (the planar hull dropped points within 1e-12 of that line), and drops
// a point exactly on an edge: corners are decided exactly. Points on x + 2y + 4z = 8.
TEST(Polytope, APolygonsCornersAreExactlyItsExtremePoints) {
  const double t = 0x1p-46;  // (the bent corner: 1.4e-14 off the chord)
  const std::vector<Vector3d> pts = {{8, 0, 0}, {0, 4, 0}, {0, 0, 2}, {4, 0, 1}, {4 + 4 * t, -2 * t, 1}, {0, 2, 1}};
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(pts, p), Status::Ok);
  ASSERT_TRUE(p.flat);
  std::vector<int> corners = p.input_index;
  std::sort(corners.begin(), corners.end());
  EXPECT_EQ(corners, (std::vector<int>{0, 1, 2, 4}));  // (3 and 5 lie on edges: 2-0 and 1-2)
  expect_valid(p);
}

// fuzz_sum campaign of 67d1226 (seed 1207019, 69,037 inputs): five points 2e52 across whose
// fifth lies 256 (1e-50 of the size) off the others' plane. Kept as that thin solid, its posed
// sum with a triangle had crossing facets 2.3e71 off their vertices. Within 64 eps of the size
// (the queries' rounding tolerance) points are flat; farther off, a solid of every corner.
TEST(Polytope, PointsWithin64EpsOfAPlaneAreFlatAndFartherOffASolid) {
  const std::vector<Vector3d> thin = {{0, 0.046875, 164},
                                      {0, 0, 0},
                                      {256, 0, -215.96875},
                                      {-2.0048271934734512e+52, -2.0048271934734512e+52, -2.0048271934734512e+52},
                                      {-1.9578390561264172e+49, -2.0048271934734512e+52, 7.6306574086370347e-305}};
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(thin, p), Status::Ok);
  EXPECT_TRUE(p.flat);
  // A unit square whose corner is lifted by h: flat at h = 2^-50 (9e-16 of the size), a
  // tetrahedron of all four corners at 2^-40 (9e-13).
  for (const double h : {0x1p-50, 0x1p-40}) {
    ASSERT_EQ(polytope_from_points({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, h}}, p), Status::Ok);
    EXPECT_EQ(p.flat, h < 0x1p-45) << h;
    EXPECT_EQ(p.vertices.size(), 4u) << h;
    expect_valid(p);
  }
}

TEST(Polytope, TooFewOrCollinearPointsAreRejected) {
  ConvexPolytope p;
  EXPECT_EQ(polytope_from_points({}, p), Status::TooFewPoints);
  EXPECT_EQ(polytope_from_points({{1, 2, 3}, {1, 2, 3}, {1, 2, 3}}, p), Status::TooFewPoints);
  EXPECT_EQ(polytope_from_points({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {3, 3, 3}}, p), Status::Collinear);
  EXPECT_EQ(polytope_from_triangle({{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}, p), Status::Collinear);
  EXPECT_EQ(polytope_from_triangle({{0, 0, 0}, {0, 0, 0}, {2, 2, 2}}, p), Status::TooFewPoints);
}

TEST(Polytope, BoxCornerCodesFollowTheAxisSigns) {
  Box b;
  b.center = Vector3d(1, 2, 3);
  b.rotation = tools::table1_rotation();
  b.half_extents = Vector3d(0.5, 1, 2);
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_box(b, p), Status::Ok);
  ASSERT_EQ(p.vertices.size(), 8u);
  for (int k = 0; k < 8; ++k) {
    const Vector3d local = b.rotation.transpose() * (p.vertices[k] - b.center);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(local[a], ((k >> a) & 1 ? 1 : -1) * b.half_extents[a], 1e-12);
  }
  expect_valid(p);
}

TEST(Polytope, InvalidBoxesAreRejected) {
  ConvexPolytope p;
  Box b;
  b.half_extents.y() = 0;
  EXPECT_EQ(polytope_from_box(b, p), Status::InvalidBox);
  b = Box{};
  b.rotation(0, 0) = -1;  // a reflection, not a rotation
  EXPECT_EQ(polytope_from_box(b, p), Status::InvalidBox);
  b = Box{};
  b.rotation *= 2;
  EXPECT_EQ(polytope_from_box(b, p), Status::InvalidBox);
}

TEST(Polytope, TriangleKeepsItsVertexOrder) {
  const Triangle t{{0, 0, 0}, {0, 1, 0}, {1, 0, 0}};
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_triangle(t, p), Status::Ok);
  EXPECT_TRUE(p.flat);
  EXPECT_EQ(p.vertices[0], t.a);
  EXPECT_EQ(p.vertices[1], t.b);
  EXPECT_EQ(p.vertices[2], t.c);
  expect_valid(p);
}

// A cube as 12 triangles with mixed orientations.
std::vector<std::vector<int>> cube_triangles() {
  return {{0, 1, 3}, {0, 3, 2}, {4, 7, 5}, {4, 6, 7}, {0, 5, 1}, {0, 4, 5},
          {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 7, 3}, {1, 5, 7}};
}

TEST(Polytope, ExplicitConvexMeshIsAcceptedAndMerged) {
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_mesh(tools::cube_points(), cube_triangles(), p), Status::Ok);
  EXPECT_EQ(p.faces.size(), 6u);
  expect_valid(p);
}

TEST(Polytope, BadExplicitMeshesAreRejected) {
  ConvexPolytope p;
  auto faces = cube_triangles();
  faces[3][1] = 8;  // out of range
  EXPECT_EQ(polytope_from_mesh(tools::cube_points(), faces, p), Status::InvalidMesh);
  faces = cube_triangles();
  faces.pop_back();  // open
  EXPECT_EQ(polytope_from_mesh(tools::cube_points(), faces, p), Status::InvalidMesh);
  faces = cube_triangles();
  faces[0] = {0, 1};  // too short
  EXPECT_EQ(polytope_from_mesh(tools::cube_points(), faces, p), Status::InvalidMesh);
  auto dented = tools::cube_points();
  dented[7] = Vector3d(0.5, 0.5, 0.5);  // pushes a corner inwards: not convex
  EXPECT_EQ(polytope_from_mesh(dented, cube_triangles(), p), Status::NotConvex);
  auto bad = tools::cube_points();
  bad[2].z() = std::nan("");
  EXPECT_EQ(polytope_from_mesh(bad, cube_triangles(), p), Status::NonFinite);
}

TEST(Polytope, SupportFunctionPicksTheExtremeVertex) {
  ConvexPolytope p;
  ASSERT_EQ(polytope_from_points(tools::cube_points(), p), Status::Ok);
  int arg = -1;
  EXPECT_DOUBLE_EQ(support(p, Vector3d(1, 2, 3), &arg), 6.0);
  EXPECT_EQ(p.vertices[arg], Vector3d(1, 1, 1));
}

TEST(Status, EveryStatusHasAMessage) {
  for (int s = 0; s <= int(Status::HullFailed); ++s) EXPECT_STRNE(to_string(Status(s)), "unknown status");
}


// Sizes at both ends of double's range get the status that names them: a tetrahedron 1e-200
// across is OutOfRange (it was "collinear": its cross products underflow), one of edge 1e80 is
// built (Qhull, which the library used, failed on it; the README accepts 1e100); a failed (empty) sum contains nothing.
TEST(Polytope, SizesAtTheEndsOfTheRange) {
  const auto tetra = [](double s) {
    return std::vector<Eigen::Vector3d>{{0, 0, 0}, {s, 0, 0}, {0, s, 0}, {0, 0, s}};
  };
  ConvexPolytope p;
  EXPECT_EQ(polytope_from_points(tetra(1e-200), p), Status::OutOfRange);
  EXPECT_EQ(polytope_from_points(tetra(1e-99), p), Status::Ok);
  ASSERT_EQ(polytope_from_points(tetra(1e80), p), Status::Ok);
  EXPECT_EQ(p.vertices.size(), 4u);
  EXPECT_EQ(p.faces.size(), 4u);
  MinkowskiSum m;
  ASSERT_EQ(minkowski_sum(p, p, m), Status::Ok);
  EXPECT_TRUE(m.euler_ok);
  EXPECT_TRUE(contains(m, Eigen::Vector3d(1e79, 1e79, 1e79)));
  EXPECT_FALSE(contains(MinkowskiSum{}, Eigen::Vector3d::Zero()));
  EXPECT_FALSE(contains(m, Eigen::Vector3d(NAN, 0, 0)));
  EXPECT_NE(std::string(to_string(Status::InvalidArgument)).find("tolerance"), std::string::npos);
  EXPECT_NE(std::string(to_string(Status::OutOfRange)).find("1e-100"), std::string::npos);
}

}  // namespace
}  // namespace minksum
