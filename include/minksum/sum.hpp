// minksum: the Minkowski sum A (+) B and difference A (-) B = A (+) (-B) of convex polytopes.
#pragma once

#include <minksum/model.hpp>
#include <minksum/shape.hpp>

#include <vector>

namespace minksum {

/// Which algorithm computes the sum.
enum class Method {
  Fast,       ///< separable supports + Gauss-map arc test with exact predicates (default)
  Reference,  ///< the paper as written: push candidate planes over all pairwise sums
  Hull,       ///< the convex hull method: the exact hull of all pairwise sums (the paper's comparator)
  Kernel,     ///< the box-box kernel (minkowski_sum of two boxes reports it); as a request: Fast
};

/// A vertex of the sum: the pair (i in A, j in B) and its coordinates a_i + b_j (or a_i - b_j).
struct SumVertex {
  int i = -1, j = -1;                               ///< support index pair (the paper's index tracking)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  ///< coordinates
};

/// Which parts of a sum a call computes (the rest is left empty): what a query or a
/// configuration-space obstacle needs, or the whole polytope.
enum class SumParts {
  Planes,    ///< the facets' planes, each with a support pair: no vertices, loops, V nor E
  Vertices,  ///< Whole's planes, vertices, V, E and F, certified as Whole is, without the loops
  Whole,     ///< planes, vertices and facet loops, certified by Euler's relation (the default)
};

/// A facet plane n . x <= offset, with one support pair (i, j) lying on it.
struct SumPlane {
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< outward unit normal
  double offset = 0;                                 ///< n . x = offset on the facet
  /// a_i + b_j lies on the facet: its loop's first vertex (the smallest pair), or with
  /// SumParts::Planes, where the facet merges features of both operands, a pair inside it.
  int i = -1, j = -1;
};

/// One facet's vertex loop: indices into MinkowskiSum::vertices, counter-clockwise from outside.
struct Loop {
  const int* first = nullptr;                       ///< its first index
  int count = 0;                                    ///< its length
  const int* begin() const { return first; }        ///< range-for support
  const int* end() const { return first + count; }  ///< range-for support
  int size() const { return count; }                ///< its length
  int operator[](int k) const { return first[k]; }  ///< index k of the loop
};

/// The Minkowski sum as an H-representation with index tracking and full topology, in flat
/// arrays (a result that is reused keeps its capacity: a loop of sums allocates only while
/// the output grows).
struct MinkowskiSum {
  std::vector<SumPlane> planes;     ///< one per facet
  std::vector<int> loop_start;      ///< F + 1 offsets: facet k's loop is loop_vertex[loop_start[k], loop_start[k + 1])
  std::vector<int> loop_vertex;     ///< the facets' loops back to back (indices into `vertices`)
  std::vector<SumVertex> vertices;  ///< sorted by (i, j)
  int V = 0, E = 0, F = 0;          ///< counts of vertices, edges and facets
  bool euler_ok = false;            ///< V - E + F == 2 and every edge has two facets (a rounded sum's point or segment core: true)
  bool corrected = false;           ///< the Section 3 hull corrector rebuilt the result
  Method method = Method::Fast;     ///< the path that produced it
  SumParts parts = SumParts::Whole;  ///< what it holds (the hull corrector's answer is whole)
  /// The radius swept around the polytope: the sum is it (+) a ball of this radius (rounded
  /// operands: their radii added; 0 for polytopes)
  double radius = 0;
  /// Facet k's vertex loop, starting at its smallest index (the plane's pair); a Whole result's only.
  Loop facet(int k) const { return {loop_vertex.data() + loop_start[k], loop_start[k + 1] - loop_start[k]}; }
};

/// (R_A A + t_A) (+) (R_B B + t_B) of two prepared shapes, each placed by its pose inside the
/// call (the overlay of their Gauss maps, Method::Fast): planes and vertices in the world
/// frame, support pairs (i, j) indexing a.polytope() and b.polytope(). O(|E_A| + |E_B| +
/// output) after one linear scan for the first support. `parts`: Planes skips the vertices
/// and loops (certified as Whole is, but for Euler's relation, which needs the loops; a flat
/// operand takes the whole path); Vertices hands back Whole without its loops. Rounded shapes
/// (a radius, a sphere, a capsule): the sum of the cores, Whole whatever `parts` asks (reading
/// it with its radius needs the loops), with `radius` the radii added; a sphere's core is a
/// point, so with a solid core the sum is that core translated; a capsule's is a segment, which
/// has no Gauss map: the hull of the pairwise sums (method Hull). Rounded cores that sum to a
/// point, a segment or a polygon (two spheres, a sphere and a capsule, two capsules, ...) give
/// that core: V 1 (E 0, F 0), V 2 (E 1, F 0) or a polygon's corners with its two sides (F 2).
/// TooFewPoints for an empty shape, InvalidPose for a pose that is not rigid,
/// DegenerateResult for polytopes (no radius) whose sum is not a solid (two coplanar flat shapes).
Status minkowski_sum(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, MinkowskiSum& out, SumParts parts = SumParts::Whole);

/// (R_A A + t_A) (-) (R_B B + t_B), the configuration-space obstacle of the placed shapes.
Status minkowski_difference(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                            const Eigen::Isometry3d& pose_b, MinkowskiSum& out, SumParts parts = SumParts::Whole);

/// A (+) B of two polytopes (the convenience entry: Method::Fast prepares both, as a
/// ConvexShape would be, on every call). Facets of coplanar support features are merged into
/// one polygon.
Status minkowski_sum(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out, Method method = Method::Fast);

/// A (+) B of two boxes through the box-box kernel's whole-polytope path (box_box_sum, active
/// ISA, one lane): its 30 planes and vertex loops (vertex i, j: box_corner codes); boxes out
/// of general position (parallel edges, an edge parallel to a face) take the general path.
Status minkowski_sum(const Box& a, const Box& b, MinkowskiSum& out);

/// A (-) B = A (+) (-B), the configuration-space obstacle; index j refers to B's vertex j.
Status minkowski_difference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out,
                            Method method = Method::Fast);

/// Index tracking (the paper's Section 4): the facet normals of a prototype sum and, per facet,
/// n . a_i and n . b_j of its support pair in the operands' own frames. Any copy of the sum with
/// A scaled by sA > 0 and moved by tA (and B by sB, tB) has offsets
/// sA (n . a_i) + sB (n . b_j) + n . (tA + tB): O(facets), no search.
struct TopologyTable {
  std::vector<double> nx, ny, nz;  ///< facet normals
  std::vector<double> pa, pb;      ///< n . a_i and n . b_j of the prototype's support pair
  std::vector<int> i, j;           ///< the support pair (index tracking)
  double sign_b = 1;               ///< -1 for a difference: B's translation enters negated
};

/// The table of a general sum or difference `m` of the operands a and b.
TopologyTable topology_table(const MinkowskiSum& m, const ConvexPolytope& a, const ConvexPolytope& b, bool difference);

/// Offsets of the copy with scales sA, sB > 0 and translations tA, tB: offset_k =
/// sA pa_k + sB pb_k + n_k . (tA + sign_b tB) (offsets: capacity >= facets). No allocation.
void instantiate(const TopologyTable& t, double sA, const Eigen::Vector3d& tA, double sB, const Eigen::Vector3d& tB,
                 double* offsets);

}  // namespace minksum
