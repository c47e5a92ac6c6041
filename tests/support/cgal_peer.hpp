// CGAL as a peer of the Minkowski sums and the exact oracle of the tests: CGAL's one
// translation unit (it is header-heavy).
#pragma once

#include <Eigen/Core>

#include <memory>
#include <vector>

namespace minksum::peers {

/// CGAL convex_hull_3 (Epick) on the |A| |B| pairwise sums, into a Surface_mesh of triangles
/// (vertices, halfedges, faces); returns its face count, and its vertices if asked.
int cgal_quickhull(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                   std::vector<Eigen::Vector3d>* vertices = nullptr);

/// Two hulls as CGAL Nef polyhedra (Epeck), built once: the operands of sum(), as
/// minksum's prepared shapes are its operands (neither build is timed with the sum).
class CgalNefOperands {
 public:
  /// Builds the exact hull of each point set and its Nef polyhedron.
  CgalNefOperands(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);
  ~CgalNefOperands();
  /// CGAL's exact Minkowski sum of the two (minkowski_sum_3, which decomposes into convex
  /// parts and unions their pairwise hulls); returns its vertex count.
  int sum() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// V, E, F of a convex polytope.
struct ExactCounts {
  int V = 0, E = 0, F = 0;
};

/// V, E, F of the hull of the pairwise sums a + s b computed exactly (Epeck, from the doubles
/// as given), with exactly coplanar triangles merged: the exact structure of A (+) B (s = 1) or
/// A (-) B (s = -1); with `facets`, each merged facet's vertices rounded to doubles, sorted.
ExactCounts exact_counts(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s,
                         std::vector<std::vector<Eigen::Vector3d>>* facets = nullptr);

/// The same for sums that are doubles exactly (integer coordinates, say; else V = E = F = -1),
/// by exact predicates on them (Epick, several times faster), and with `facets` each merged
/// facet's vertices (the points a_i + s b_j), sorted lexicographically.
ExactCounts exact_structure(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s,
                            std::vector<std::vector<Eigen::Vector3d>>* facets);

/// The distance between the hulls of two point sets by CGAL's exact polytope distance (an
/// LP-type solver over the points, exact Gmpzf arithmetic): its squared distance is an exact
/// ratio, rounded once.
double cgal_distance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);

}  // namespace minksum::peers
