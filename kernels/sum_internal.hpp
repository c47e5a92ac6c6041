// Shared internals of the two Minkowski-sum paths.
#pragma once

#include <minksum/sum.hpp>

#include <cstdint>
#include <utility>
#include <vector>

namespace minksum::detail {

/// A facet as its normal and its loop of support pairs (i in A, j in B), CCW from outside.
struct FacetLoop {
  Eigen::Vector3d normal;
  std::vector<std::pair<int, int>> loop;
};

/// Builds `out` from facet loops over A (+) B: drops repeated pairs and facets with fewer
/// than three distinct pairs, numbers the vertices, computes offsets, V, E, F and Euler.
void assemble(const ConvexPolytope& a, const ConvexPolytope& b, std::vector<FacetLoop>& facets,
              MinkowskiSum& out);

/// The paper's Section 3 corrector: rebuilds A (+) B from the hull of all pairwise sums.
Status hull_corrector(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out);

/// The reference path (the paper as written) on A (+) B.
void sum_reference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out);

/// The fast path (separable supports, Gauss-map arc test) on A (+) B; false if its Gauss-map
/// location failed, which only an invalid polytope can cause.
bool sum_fast(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out);

/// The fast path for operands of at most 64 vertices, faces and edges, in general position:
/// every decision in double with a margin (sum_small.cpp). False, with `out` unspecified, when
/// it does not apply or a margin fails; true with a complete result otherwise.
bool sum_small(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out);

/// Through the active ISA, for n <= 64 normals N and k <= 64 edge directions d (direction arrays
/// readable to k rounded up to 8): bit e of positive[v] is set iff d_e . N_v > tol, and *unsure
/// iff some |d_e . N_v| <= tol.
void edge_signs(const double* nx, const double* ny, const double* nz, int n, const double* dx,
                const double* dy, const double* dz, int k, double tol, std::uint64_t* positive,
                bool* unsure);

/// Through the active ISA, for n rows up[f] of edge bits and v <= 64 vertices (edges and ends
/// readable to v rounded up to 8, the padding with ends all ones): top[f] is the first vertex
/// j with (up[f] & edges[j]) == ends[j]; false if some row has none.
bool support_sinks(const std::uint64_t* up, int n, const std::uint64_t* edges,
                   const std::uint64_t* ends, int v, int* top);

}  // namespace minksum::detail
