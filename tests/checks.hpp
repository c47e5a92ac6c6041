// Independent checks of a Minkowski sum against its inputs (brute force), shared by the tests.
#pragma once

#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/mesh_io.hpp"

namespace minksum::peers {
struct ExactCounts;
}  // namespace minksum::peers

namespace minksum::test {

/// The path of `name` in ../shared/data (the bunnies), whether or not it exists.
std::string data_path(const std::string& name);

/// ../shared/data/`name` (a Stanford bunny) if this machine has it, else a generated bumpy
/// sphere of 4 rings^2 triangles, so that mesh tests run everywhere.
tools::Mesh test_mesh(const std::string& name, int fallback_rings);

/// n scaled by the environment variable MINKSUM_TEST_SCALE (default 1; the sanitizer run of
/// ci/test uses a fraction), at least `at_least`: the sizes of the randomized tests. A test
/// whose cases span bands or kinds (near, touching, far) passes their number, so that each
/// keeps a case under the sanitizer: the cost per case shrinks, not the set of bands.
int scaled(int n, int at_least = 1);

/// A test mesh (test_mesh), its octree (default options) and a workspace for it against itself.
struct MeshSetup {
  tools::Mesh mesh;
  Octree tree;
  MeshWorkspace ws;
};
/// Builds a MeshSetup; a failed octree build fails the calling test.
std::unique_ptr<MeshSetup> mesh_setup(const std::string& name, int fallback_rings);

/// A random pose: uniform rotation, translation in [-reach, reach]^3.
Eigen::Isometry3d random_pose(std::mt19937_64& rng, double reach);

/// Every pairwise sum a + s b of the input points (s = +1 sum, -1 difference).
std::vector<Eigen::Vector3d> pairwise(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                      double s);

/// Checks `m` = A (+) sB against the raw input points, by brute force:
/// each vertex (i, j) equals a_i + s b_j; every pairwise sum is inside every plane (within
/// tol * size); the loops are outward, planar and on their planes; Euler holds; and the support
/// function of m's vertices equals h_A + h_B in `directions` random directions and (for
/// operands of up to 4000 edge pairs) at every candidate facet normal of the exact sum: the
/// operands' face normals and the crosses of their edges (relative error <= support_tol).
testing::AssertionResult valid_sum(const std::vector<Eigen::Vector3d>& a_pts, const std::vector<Eigen::Vector3d>& b_pts,
                                   double s, const ConvexPolytope& A, const ConvexPolytope& B, const MinkowskiSum& m,
                                   double tol, double support_tol, int directions = 1000, unsigned seed = 1);

/// The same polytope: same V, E, F and, facet by facet, the same vertex pairs, and planes
/// that agree at those vertices within tol * size.
testing::AssertionResult same_sum(const MinkowskiSum& x, const MinkowskiSum& y, double tol);

/// A facet of the exact hull of the pairwise sums a + s b (CGAL's exact kernel, an oracle
/// independent of the library and of its own hull).
struct ExactFacet {
  Eigen::Vector3d normal;               ///< outward, unit (from the vertices, rounded)
  double offset = 0;                    ///< normal . x = offset on the facet
  std::vector<Eigen::Vector3d> points;  ///< its vertices (rounded to doubles), sorted
};

/// The exact hull of the pairwise sums a + s b of a solid sum, with coplanar triangles merged
/// (peers::exact_counts, whose V, E, F go to `counts` if given).
std::vector<ExactFacet> exact_hull(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                   double s, peers::ExactCounts* counts = nullptr);

/// Whether every a_i + s b_j is a double exactly (Knuth's two-sum leaves no error): where
/// it is not, the hull method's result (the exact hull of the sums as doubles) may differ
/// from the exact hull of the exact sums.
bool sums_are_doubles(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s);

/// m is the exact hull of the pairwise sums a + s b: the same V, E, F as CGAL's exact hull, and
/// facet by facet the same vertices, equal within tol * size (tol = 0: exactly, for sums that are
/// doubles).
testing::AssertionResult equals_exact_hull(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                           double s, const MinkowskiSum& m, double tol);

/// m is the planes level (SumParts::Planes) of the sum a + s b, a and b the point sets its pairs
/// index: one plane per facet of CGAL's exact hull, holding the facet's vertices within
/// tol * size, and each plane's pair a_i + s b_j on it.
testing::AssertionResult equals_exact_planes(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                             double s, const MinkowskiSum& m, double tol);

/// m is the vertices level (SumParts::Vertices) of the sum a + s b: CGAL's exact V, E and F, its
/// vertices each a_i + s b_j in (i, j) order, one per exact vertex within tol * size, and its
/// planes as equals_exact_planes asks; no loops.
testing::AssertionResult equals_exact_vertices(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                                               double s, const MinkowskiSum& m, double tol);

/// What brute force says of two convex polytopes.
struct Oracle {
  bool overlap;         ///< no separating axis among face normals and edge crosses
  double distance;      ///< min over vertex-face and edge-edge distances (0 if overlapping)
  double depth;         ///< smallest overlap over those axes (0 if separated)
  double max_distance;  ///< max over vertex pairs
};

/// Brute force on two polytopes: the separating axis theorem over face normals and edge
/// crosses, vertex-face and edge-edge distances, all vertex pairs.
Oracle brute_force(const ConvexPolytope& a, const ConvexPolytope& b);

/// The polytope p moved by `pose` with its structure kept (same indices): vertices, normals and
/// offsets transformed, as a user holding world-frame polytopes would build them.
ConvexPolytope transformed(const ConvexPolytope& p, const Eigen::Isometry3d& pose);

/// Distance between the segments [p0, p1] and [q0, q1].
double segment_distance(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1, const Eigen::Vector3d& q0,
                        const Eigen::Vector3d& q1);

}  // namespace minksum::test
