// Shared internals of the Minkowski-sum paths.
#pragma once

#include <minksum/sum.hpp>

#include <utility>
#include <vector>

namespace minksum::detail {

/// A facet as its normal and its loop of support pairs (i in A, j in B), CCW from outside.
struct FacetLoop {
  Eigen::Vector3d normal;
  std::vector<std::pair<int, int>> loop;
};

/// Every directed edge of the loops appears once, and its reverse once: a closed 2-manifold.
bool closed_manifold(const MinkowskiSum& m);

/// Builds `out` from facet loops over the points a_i + b_j: drops repeated pairs and facets
/// with fewer than three distinct pairs, numbers the vertices, computes offsets, V, E, F and
/// Euler (with the closed-manifold check).
void assemble(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
              std::vector<FacetLoop>& facets, MinkowskiSum& out);

/// The paper's Section 3 corrector: rebuilds the sum of the point sets a and b (B already
/// negated for a difference) from the hull of all pairwise sums.
Status hull_corrector(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, MinkowskiSum& out);

/// The reference path (the paper as written) on A (+) B.
void sum_reference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out);

}  // namespace minksum::detail
