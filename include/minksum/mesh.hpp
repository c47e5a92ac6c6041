// minksum: exact minimum distance between two triangle meshes through octrees of cubes (the
// paper's Section 5.1): node pairs are culled with cube-cube bounds that share one relative
// rotation per query (topological invariance, Section 4), and the surviving triangle pairs get
// the exact triangle-triangle distance.
#pragma once

#include <minksum/model.hpp>
#include <minksum/query.hpp>

#include <array>
#include <vector>

namespace minksum {

/// How an octree is built. The octree adapts to the mesh: a node is split while it holds more
/// than leaf_size triangles, each going to the child cube that holds its centroid; where all go
/// to one child (a dense patch), the cube narrows in on them without a level. Leaves follow the
/// local density; there is no global depth.
struct OctreeOptions {
  int max_depth = -1;   ///< levels below the root, at most (-1: 20; at most 24)
  int leaf_size = 64;   ///< a node with more triangles than this is split
};

/// An octree of cubes over one triangle mesh, in flat arrays (built once, read-only after).
/// Each triangle is listed once, in the leaf whose cube holds its centroid; each node bounds its
/// triangles whole (so its box may reach beyond its cube).
struct Octree {
  /// One cube; children are contiguous and only non-empty ones are kept. Besides the cube,
  /// two bounds of the node's triangles: their box (bounding box, axis-aligned in the mesh's
  /// frame) and their slab (between two planes of the mean normal).
  struct Node {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();  ///< cube centre (mesh frame)
    double half = 0;         ///< half side length
    Eigen::Vector3d box_center = Eigen::Vector3d::Zero();  ///< tight box centre
    Eigen::Vector3d box_half = Eigen::Vector3d::Zero();    ///< tight box half extents
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();     ///< slab normal (unit)
    double slab_lo = 0, slab_hi = 0;  ///< normal . x of the triangles lies in [slab_lo, slab_hi]
    int first_child = -1;    ///< index of the first child, -1 for a leaf
    int child_count = 0;     ///< number of children
    int first = 0;           ///< leaf: first entry in `items`
    int count = 0;           ///< leaf: number of triangles listed
    int corner_first = 0;    ///< leaf: first of its triangles' distinct corners in `corners`
    int corner_count = 0;    ///< leaf: number of distinct corners
  };
  std::vector<Eigen::Vector3d> vertices;         ///< the mesh's vertices (a copy)
  std::vector<std::array<int, 3>> triangles;     ///< the mesh's triangles (a copy)
  std::vector<Eigen::Vector4d> spheres;          ///< per triangle: bounding sphere centre, radius
  std::vector<Eigen::Vector3d> normals;          ///< per triangle: unit normal (zero if degenerate)
  std::vector<Node> nodes;                       ///< nodes[0] is the root
  std::vector<int> items;                        ///< triangle indices of the leaves
  std::vector<Eigen::Vector3d> corners;          ///< per leaf: its triangles' distinct corners
  std::vector<Eigen::Vector3d> item_corners;     ///< per entry of `items`: its triangle's 3 corners
  int depth = 0;                                 ///< deepest level reached
  int leaves = 0;                                ///< number of leaves
  int max_leaf = 0;                              ///< most triangles in one leaf
  bool points = false;                           ///< built from a point cloud (every triangle a point)
  size_t bytes() const;                          ///< memory held by the arrays
};

/// Builds the octree of a mesh. Unused vertices, boundary and non-manifold edges and
/// degenerate triangles are accepted; NaN/Inf coordinates (NonFinite), indices out of range
/// (InvalidMesh) and meshes without triangles (TooFewPoints) are rejected. A triangle with
/// exactly the corners of an earlier one is not listed in the leaves (it cannot be nearer).
Status build_octree(const std::vector<Eigen::Vector3d>& vertices,
                    const std::vector<std::array<int, 3>>& triangles, Octree& out,
                    const OctreeOptions& options = {});

/// Builds the octree of a point cloud (points without faces, as from a scanner, the paper's
/// Section 5.1 closing remark): point k becomes the zero-area triangle (k, k, k), so
/// mesh_distance gives the exact closest pair of points of two clouds, or of a cloud and a mesh,
/// and triangle_a/b name the points. Duplicate points are listed once; the same rejections as
/// for a mesh (TooFewPoints for no points).
Status build_octree(const std::vector<Eigen::Vector3d>& points, Octree& out, const OctreeOptions& options = {});

/// Rigid placement of mesh B in mesh A's frame: x_A = rotation * x_B + translation.
struct Pose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();      ///< proper rotation
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();       ///< offset
};

/// Scratch memory of mesh_distance, sized once for a pair of octrees so that queries never
/// allocate (make_workspace); reuse it for every query of that pair.
struct MeshWorkspace {
  /// A node pair still to visit, with its squared distance bound.
  struct Entry {
    int a = 0, b = 0;    ///< node of A, node of B
    double bound2 = 0;   ///< lower bound of their squared distance
  };
  /// Node pairs still to visit: a heap of what it holds beyond 8 (depth_a + depth_b) + 16
  /// (4,096 from make_workspace), then that reserve for the depth-first fallback.
  std::vector<Entry> stack;
  std::vector<Eigen::Vector3d> moved_center; ///< B's sphere centres in A's frame, on demand
  std::vector<unsigned> center_stamp;        ///< query stamp per triangle of B
  std::vector<unsigned> seen_a, seen_b;      ///< query stamp per candidate triangle
  std::vector<int> near_b;                   ///< triangles of B's leaf near A's leaf
  std::vector<double> near_x, near_y, near_z, near_r;  ///< their spheres (A's frame)
  std::vector<double> near_lo;               ///< their lowest corners along the leaves' line
  std::vector<double> proj_a, proj_b;        ///< per leaf triangle: A's highest, B's lowest corner there
  std::vector<int> pass_a;                   ///< A's leaf triangles near B's leaf, nearest first
  std::vector<Eigen::Vector3d> near_corners; ///< their corners (A's frame), three each
  std::vector<Eigen::Vector3d> near_normal;  ///< their unit normals (A's frame)
  std::vector<int> hits;                     ///< those near one triangle of A
  std::vector<Eigen::Vector3d> parts;        ///< mesh_contact: corners of the parts inside
  std::vector<int> part_start;               ///< mesh_contact: where each part's corners start
  unsigned stamp = 0;                        ///< current query
};

/// Sizes a workspace for queries between a and b.
void make_workspace(const Octree& a, const Octree& b, MeshWorkspace& ws);

/// The answer of one mesh-mesh distance query, with its statistics.
struct MeshDistance {
  double distance = 0;        ///< exact minimum distance (0 when the meshes intersect)
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< closest point on A (A's frame)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< closest point on B (A's frame)
  int triangle_a = -1, triangle_b = -1;  ///< the triangles holding them
  bool intersecting = false;  ///< the meshes share a point
  double first_bound = 0;     ///< U of the first leaf pair reached (its boxes' max distance)
  long node_pairs = 0;        ///< node pairs whose bound was evaluated
  long leaf_pairs = 0;        ///< leaf pairs opened (their triangles tested)
  long triangle_pairs = 0;    ///< exact triangle-triangle distances computed
  int candidates_a = 0, candidates_b = 0;  ///< distinct triangles that reached that stage
  double culled_percent_a = 0, culled_percent_b = 0;  ///< 100 * (1 - candidates / triangles)
};

/// Exact minimum distance between mesh A and mesh B placed by `pose`: best-first
/// branch-and-bound over node pairs (a fixed-size heap, then depth first if it fills), pruning
/// pairs whose distance bound reaches the best triangle distance found so far. No allocation with a workspace from
/// make_workspace(a, b); InvalidBox for a pose that is not a finite proper rotation.
Status mesh_distance(const Octree& a, const Octree& b, const Pose& pose, MeshWorkspace& ws,
                     MeshDistance& out);

/// The same exact distance, with the search seeded by the last answer's triangle pair (see
/// ProximityCache): re-evaluated at the new pose, its distance bounds the search from the
/// first node pair on. A seed only prunes more, so the worst case is the cold search's plus
/// one triangle distance; the answer's distance is the cold one (ties may name another pair
/// at the same distance).
Status mesh_distance(const Octree& a, const Octree& b, const Pose& pose, MeshWorkspace& ws, ProximityCache& cache,
                     MeshDistance& out);

/// How a convex tool touches a mesh (haptic rendering): the parts of the mesh's triangles
/// inside the tool, and how far the tool must move to push them all out.
struct MeshContact {
  bool intersecting = false;   ///< some triangle has a part inside the tool
  double depth = 0;            ///< how far the tool must move along `direction` to clear them
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();  ///< unit push-out direction
  Eigen::Vector3d point = Eigen::Vector3d::Zero();      ///< the part's corner that needs it most
  int triangle = -1;           ///< the triangle of that corner
  int tested = 0;              ///< triangles that were clipped
  bool overflow = false;       ///< over kMaxContactTriangles overlapped: the first ones count
};

/// Most hull vertices a tool may have in mesh_contact (its fixed scratch space).
constexpr int kMaxToolVertices = 256;
/// Most overlapped triangles one mesh_contact call gathers (beyond: flagged, ignored).
constexpr int kMaxContactTriangles = 2048;

/// Contact of a convex tool (a shape prepared once in its own frame, placed in the mesh's
/// frame by a rigid pose on every call) with mesh A. Each triangle whose box meets the tool's
/// box is clipped by the tool's face planes; the parts left are inside the tool. Their summed area vector (triangle winding:
/// counter-clockwise = outward) gives the push-out direction u, which turns continuously as
/// the tool slides over a tessellated surface; the depth is the largest distance, over the
/// parts' corners p, that p travels along -u inside the tool. No allocation. InvalidMesh if the
/// tool is flat or has more than kMaxToolVertices vertices; the workspace is any made by
/// make_workspace (its contact buffers are sized there); TooFewPoints for an empty tool,
/// InvalidPose for a pose that is not rigid.
Status mesh_contact(const Octree& a, const ConvexShape& tool, const Eigen::Isometry3d& pose, MeshWorkspace& ws,
                    MeshContact& out);

}  // namespace minksum
