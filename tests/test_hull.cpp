// Polytopes from points against CGAL's exact hull (Epeck, coplanar triangles merged exactly:
// peers::exact_counts): the same V, E, F and, facet by facet, the same vertices, on random
// points, integer grids (ties everywhere), points on a sphere, CAD parts, clusters nearly
// coplanar, duplicates and both ends of the range; and the sums of the CAD parts with a box and
// a tessellated cylinder against the exact hull of their pairwise sums.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <random>

#include "checks.hpp"
#include "support/cgal_peer.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Vector3d;

bool lex_less(const Vector3d& x, const Vector3d& y) {
  return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
}

// P is the exact hull of `points`: CGAL's V, E, F, and each face's vertex set one of CGAL's
// facets' (both as sorted lists of points, compared exactly); each loop turns counter-clockwise
// about its face's normal, which points out (every vertex at or below its plane); and every
// vertex is the input point its input_index names.
testing::AssertionResult equals_exact_hull(const std::vector<Vector3d>& points, const ConvexPolytope& P) {
  std::vector<std::vector<Vector3d>> exact;
  const peers::ExactCounts c = peers::exact_counts(points, {Vector3d::Zero()}, 1, &exact);
  if (int(P.vertices.size()) != c.V || int(P.edges.size()) != c.E || int(P.faces.size()) != c.F)
    return testing::AssertionFailure() << "V/E/F " << P.vertices.size() << "/" << P.edges.size() << "/"
                                       << P.faces.size() << ", exact " << c.V << "/" << c.E << "/" << c.F;
  for (size_t k = 0; k < P.vertices.size(); ++k)
    if (P.input_index[k] < 0 || P.input_index[k] >= int(points.size()) || points[size_t(P.input_index[k])] != P.vertices[k])
      return testing::AssertionFailure() << "vertex " << k << " is not the input point it names";
  double size = 0;
  for (const Vector3d& v : P.vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  // Each loop turns counter-clockwise: no corner clearly clockwise (an exact corner between
  // nearly collinear neighbours has a turn that rounds to about 0) and a positive area.
  std::vector<std::vector<Vector3d>> faces;
  for (const Face& f : P.faces) {
    const int n = int(f.loop.size());
    Vector3d area = Vector3d::Zero();
    for (int k = 0; k < n; ++k) {
      const Vector3d &p = P.vertices[size_t(f.loop[k])], &q = P.vertices[size_t(f.loop[(k + 1) % n])],
                     &r = P.vertices[size_t(f.loop[(k + 2) % n])];
      area += p.cross(q);
      if ((q - p).cross(r - q).dot(f.normal) < -1e-14 * (q - p).norm() * (r - q).norm())
        return testing::AssertionFailure() << "a loop turns clockwise";
    }
    if (!(area.dot(f.normal) > 0)) return testing::AssertionFailure() << "a loop runs clockwise";
    for (const Vector3d& v : P.vertices)
      if (f.normal.dot(v) > f.offset + 1e-12 * size) return testing::AssertionFailure() << "a face looks inward";
    std::vector<Vector3d> set;
    for (int v : f.loop) set.push_back(P.vertices[size_t(v)]);
    std::sort(set.begin(), set.end(), lex_less);
    faces.push_back(std::move(set));
  }
  const auto by_points = [](const std::vector<Vector3d>& x, const std::vector<Vector3d>& y) {
    return std::lexicographical_compare(x.begin(), x.end(), y.begin(), y.end(), lex_less);
  };
  std::sort(faces.begin(), faces.end(), by_points);
  std::sort(exact.begin(), exact.end(), by_points);
  if (faces != exact) return testing::AssertionFailure() << "a face's vertices differ from the exact facet's";
  return testing::AssertionSuccess();
}

void expect_exact(const std::vector<Vector3d>& points, const std::string& what) {
  ConvexPolytope P;
  ASSERT_EQ(polytope_from_points(points, P), Status::Ok) << what;
  EXPECT_TRUE(equals_exact_hull(points, P)) << what;
}

std::vector<Vector3d> uniform(std::mt19937_64& rng, int n, double lo, double hi) {
  std::uniform_real_distribution<double> u(lo, hi);
  std::vector<Vector3d> p;
  for (int k = 0; k < n; ++k) p.emplace_back(u(rng), u(rng), u(rng));
  return p;
}

TEST(ExactHull, RandomPointsAndBothEndsOfTheRange) {
  std::mt19937_64 rng(1);
  for (int c = 0; c < test::scaled(40, 4); ++c) {
    const auto p = uniform(rng, 5 + c * 5, -1, 1);
    expect_exact(p, "random " + std::to_string(c));
    if (c % 4 == 0) {
      expect_exact(tools::scaled(p, 1e100), "random at 1e100 " + std::to_string(c));
      expect_exact(tools::scaled(p, 1e-100), "random at 1e-100 " + std::to_string(c));
    }
  }
}

// Random subsets of the integer grid {-3 ... 3}^3: coplanar and collinear points, and faces
// with points inside their edges, on every input.
TEST(ExactHull, IntegerGrids) {
  std::mt19937_64 rng(2);
  std::uniform_int_distribution<int> coordinate(-3, 3);
  for (int c = 0; c < test::scaled(60, 6); ++c) {
    std::vector<Vector3d> p;
    const int n = 8 + c;
    while (int(p.size()) < n) p.emplace_back(coordinate(rng), coordinate(rng), coordinate(rng));
    ConvexPolytope P;
    if (polytope_from_points(p, P) == Status::Ok && !P.flat) EXPECT_TRUE(equals_exact_hull(p, P)) << "grid " << c;
  }
  std::vector<Vector3d> whole;  // the whole 7^3 grid: a cube of 8 corners, 343 points on or in it
  for (int x = -3; x <= 3; ++x)
    for (int y = -3; y <= 3; ++y)
      for (int z = -3; z <= 3; ++z) whole.emplace_back(x, y, z);
  expect_exact(whole, "the whole grid");
}

TEST(ExactHull, PointsOnASphere) {
  for (int n : {8, 16, 64, 256, 1024}) expect_exact(tools::sphere_points(n, unsigned(n)), "sphere " + std::to_string(n));
}

// Each face of the cube [-1, 1]^3 holds random points lifted off it by -1e-12, 0 or 1e-12: the
// lifted ones make the face a cluster of slivers (or bury themselves), exactly as their doubles say.
TEST(ExactHull, ClustersNearlyCoplanar) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  std::uniform_int_distribution<int> lift(-1, 1);
  for (int c = 0; c < test::scaled(10, 2); ++c) {
    std::vector<Vector3d> p = tools::cube_points();
    for (int face = 0; face < 6; ++face)
      for (int k = 0; k < 6; ++k) {
        Vector3d x(u(rng), u(rng), 0);
        x.z() = (face % 2 ? -1 : 1) * (1 + 1e-12 * lift(rng));
        std::swap(x[2], x[face / 2]);
        p.push_back(x);
      }
    expect_exact(p, "cluster " + std::to_string(c));
  }
}

// Every point repeated up to three times, shuffled: the first of each keeps its index.
TEST(ExactHull, Duplicates) {
  std::mt19937_64 rng(4);
  for (int c = 0; c < test::scaled(10, 2); ++c) {
    const auto base = c % 2 ? uniform(rng, 30, -1, 1) : tools::cube_points();
    std::vector<Vector3d> p;
    for (const Vector3d& x : base)
      for (int r = 0; r <= int(rng() % 3); ++r) p.push_back(x);
    std::shuffle(p.begin(), p.end(), rng);
    ConvexPolytope P;
    ASSERT_EQ(polytope_from_points(p, P), Status::Ok);
    EXPECT_TRUE(equals_exact_hull(p, P)) << "duplicates " << c;
    for (size_t k = 0; k < P.vertices.size(); ++k)
      EXPECT_EQ(std::find(p.begin(), p.end(), P.vertices[k]) - p.begin(), P.input_index[k]) << "not the first copy";
  }
}

// The ten CAD parts of libcgal-demo, their vertex lists as given (fandisk: 6,475 points whose
// hull Qhull gave as 204/341 vertices/facets, the exact one 207/345); and their sums with a box
// and a 24-sided cylinder of a sixteenth of the part's size, against the exact hull of the
// pairwise sums: 20 of 20.
TEST(ExactHull, CadPartsAndTheirSums) {
  const auto parts = tools::cad_parts();
  int found = 0;
  for (const std::string& name : parts) {
    std::vector<Vector3d> points;
    if (!tools::cgal_demo_points(name, points)) continue;
    ++found;
    ConvexPolytope A;
    ASSERT_EQ(polytope_from_points(points, A), Status::Ok) << name;
    EXPECT_TRUE(equals_exact_hull(points, A)) << name;
    Vector3d lo = A.vertices[0], hi = lo;
    for (const Vector3d& v : A.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double r = (hi - lo).norm() / 16;
    const std::vector<Vector3d> box = tools::scaled(tools::cube_points(), r),
                                cylinder = tools::cos_sin_prism(24, r, -r, r);
    for (const auto* b : {&box, &cylinder}) {
      ConvexPolytope B;
      ASSERT_EQ(polytope_from_points(*b, B), Status::Ok);
      MinkowskiSum m;
      ASSERT_EQ(minkowski_sum(A, B, m), Status::Ok) << name;
      EXPECT_TRUE(test::equals_exact_hull(A.vertices, B.vertices, 1, m, 1e-12)) << name << (b == &box ? " + box" : " + cylinder");
    }
  }
  EXPECT_EQ(found, int(parts.size())) << "libcgal-demo's meshes are missing (ci/install-deps installs them)";
}

}  // namespace
}  // namespace minksum
