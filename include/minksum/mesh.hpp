// minksum: exact minimum distance between two triangle meshes through octrees of cubes (the
// paper's Section 5.1): node pairs are culled with cube-cube bounds that share one relative
// rotation per query (topological invariance, Section 4), and the surviving triangle pairs get
// the exact triangle-triangle distance.
#pragma once

#include <minksum/model.hpp>
#include <minksum/query.hpp>

#include <array>
#include <memory>
#include <vector>

namespace minksum {

/// How an octree is built. The octree adapts to the mesh: a node is split while it holds more
/// than leaf_size triangles, each going to the child cube that holds its centroid; where all go
/// to one child (a dense patch), the cube narrows in on them without a level. Leaves follow the
/// local density; there is no global depth.
struct OctreeOptions {
  int max_depth = -1;  ///< levels below the root, at most (-1: 20; at most 24)
  int leaf_size = 64;  ///< a node with more triangles than this is split
};

/// An octree of cubes over one triangle mesh, in flat arrays (built once, read-only after).
/// Each triangle is listed once, in the leaf whose cube holds its centroid; each node bounds its
/// triangles whole (so its box may reach beyond its cube).
struct Octree {
  /// One cube; children are contiguous and only non-empty ones are kept. Besides the cube,
  /// two bounds of the node's triangles: their box (bounding box, axis-aligned in the mesh's
  /// frame) and their slab (between two planes of the mean normal, or of the principal axis of
  /// the unoriented normals where that is under a quarter as wide: both sheets of a thin shell).
  struct Node {
    Eigen::Vector3d center = Eigen::Vector3d::Zero();      ///< cube centre (mesh frame)
    double half = 0;                                       ///< half side length
    Eigen::Vector3d box_center = Eigen::Vector3d::Zero();  ///< tight box centre
    Eigen::Vector3d box_half = Eigen::Vector3d::Zero();    ///< tight box half extents
    Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();     ///< slab normal (unit)
    double slab_lo = 0, slab_hi = 0;                       ///< normal . x of the triangles lies in [slab_lo, slab_hi]
    int first_child = -1;                                  ///< index of the first child, -1 for a leaf
    int child_count = 0;                                   ///< number of children
    int first = 0;                                         ///< leaf: first entry in `items`
    int count = 0;                                         ///< leaf: number of triangles listed
    int corner_first = 0;  ///< leaf: first of its triangles' distinct corners in `corners`
    int corner_count = 0;  ///< leaf: number of distinct corners
  };
  std::vector<Eigen::Vector3d> vertices;      ///< the mesh's vertices (a copy)
  std::vector<std::array<int, 3>> triangles;  ///< the mesh's triangles (a copy)
  std::vector<Eigen::Vector4d> spheres;       ///< per triangle: bounding sphere centre, radius
  std::vector<Eigen::Vector3d> normals;       ///< per triangle: unit normal (zero if degenerate)
  std::vector<Node> nodes;                    ///< nodes[0] is the root
  std::vector<int> items;                     ///< triangle indices of the leaves
  std::vector<Eigen::Vector3d> corners;       ///< per leaf: its triangles' distinct corners
  std::vector<Eigen::Vector3d> item_corners;  ///< per entry of `items`: its triangle's 3 corners
  int depth = 0;                              ///< deepest level reached
  int leaves = 0;                             ///< number of leaves
  int max_leaf = 0;                           ///< most triangles in one leaf
  bool points = false;                        ///< built from a point cloud (every triangle a point)
  size_t bytes() const;                       ///< memory held by the arrays
};

/// Builds the octree of a mesh. Unused vertices, boundary and non-manifold edges and
/// degenerate triangles are accepted; NaN/Inf coordinates (NonFinite), indices out of range
/// (InvalidMesh), meshes without triangles (EmptyMesh), coordinates past kMaxCoordinate or a
/// mesh both smaller and nearer the origin than kMinExtent, but not a single point (OutOfRange),
/// and options out of range (a leaf size under 1, a depth past 24: InvalidArgument) are
/// rejected. Every answer on it scales with the scene in that range. A triangle with
/// exactly the corners of an earlier one is not listed in the leaves (it cannot be nearer).
Status build_octree(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles,
                    Octree& out, const OctreeOptions& options = {});

/// Builds the octree of a point cloud (points without faces, as from a scanner, the paper's
/// Section 5.1 closing remark): point k becomes the zero-area triangle (k, k, k), so
/// mesh_distance gives the exact closest pair of points of two clouds, or of a cloud and a mesh,
/// and triangle_a/b name the points. Duplicate points are listed once; the same rejections as
/// for a mesh (EmptyMesh for no points).
Status build_octree(const std::vector<Eigen::Vector3d>& points, Octree& out, const OctreeOptions& options = {});

namespace detail {
struct MeshScratch;
}  // namespace detail

class MeshWorkspace;

/// Node pairs the best-first search holds in its heap by default; past that it goes depth first.
constexpr int kMeshHeapPairs = 4096;

/// Sizes a workspace for queries between a and b (heap_pairs >= 1: the search's heap).
void make_workspace(const Octree& a, const Octree& b, MeshWorkspace& ws, int heap_pairs = kMeshHeapPairs);

/// Scratch memory of mesh_distance and mesh_contact, sized once for a pair of octrees by
/// make_workspace so that queries never allocate; reuse it for every query of that pair. Its
/// layout is the library's own. An empty workspace (not from make_workspace), or one made for
/// other meshes, gets WorkspaceMismatch.
class MeshWorkspace {
 public:
  MeshWorkspace();                                           ///< empty
  MeshWorkspace(const MeshWorkspace& other);                 ///< a copy of the scratch
  MeshWorkspace(MeshWorkspace&& other) noexcept;             ///< takes the scratch
  MeshWorkspace& operator=(const MeshWorkspace& other);      ///< a copy of the scratch
  MeshWorkspace& operator=(MeshWorkspace&& other) noexcept;  ///< takes the scratch
  ~MeshWorkspace();                                          ///< frees the scratch
  /// The scratch (null when empty), for the library's queries.
  detail::MeshScratch* scratch() { return scratch_.get(); }

 private:
  friend void make_workspace(const Octree& a, const Octree& b, MeshWorkspace& ws, int heap_pairs);
  std::unique_ptr<detail::MeshScratch> scratch_;
};

/// What one mesh-mesh distance query did (for benchmarks and tuning; no answer depends on it).
struct MeshStats {
  double first_bound = 0;                             ///< U of the first leaf pair reached (its boxes' max distance)
  long node_pairs = 0;                                ///< node pairs whose bound was evaluated
  long leaf_pairs = 0;                                ///< leaf pairs opened (their triangles tested)
  long triangle_pairs = 0;                            ///< exact triangle-triangle distances computed
  int candidates_a = 0, candidates_b = 0;             ///< distinct triangles that reached that stage
  double culled_percent_a = 0, culled_percent_b = 0;  ///< 100 * (1 - candidates / triangles)
};

/// The answer of one mesh-mesh distance query, and apart from it the query's statistics.
struct MeshDistance {
  double distance = 0;                                ///< exact minimum distance (0 when the meshes intersect)
  Eigen::Vector3d point_a = Eigen::Vector3d::Zero();  ///< closest point on A (world frame)
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< closest point on B (world frame)
  int triangle_a = -1, triangle_b = -1;               ///< the triangles holding them
  bool intersecting = false;                          ///< the meshes share a point
  MeshStats stats;                                    ///< what the search did
};

/// Exact minimum distance between mesh A and mesh B, each placed in the world by its pose (as
/// every query takes its operands; the points come back in the world frame): best-first
/// branch-and-bound over node pairs (a fixed-size heap, then depth first if it fills), pruning
/// pairs whose distance bound reaches the best triangle distance found so far. B is placed in
/// A's frame by pose_a^-1 pose_b (with A at the identity, exactly pose_b). No allocation with a
/// workspace from make_workspace(a, b) (WorkspaceMismatch with another); InvalidPose for a pose
/// that is not rigid.
Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const Octree& b, const Eigen::Isometry3d& pose_b,
                     MeshWorkspace& ws, MeshDistance& out);

/// The same exact distance, with the search seeded by the last answer's triangle pair (see
/// ProximityCache): re-evaluated at the new pose, its distance bounds the search from the
/// first node pair on. A seed only prunes more, so the worst case is the cold search's plus
/// one triangle distance; the answer's distance is the cold one (ties may name another pair
/// at the same distance).
Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const Octree& b, const Eigen::Isometry3d& pose_b,
                     MeshWorkspace& ws, ProximityCache& cache, MeshDistance& out);

/// Exact minimum distance between a convex shape (any kind: a polytope, box or triangle, a
/// sphere, a capsule, any of them rounded) and mesh A, each placed in the world by its pose.
/// The shape is solid and the mesh a surface: a triangle inside the shape touches it. The
/// search runs on the shape's core, its bounds grown by the radius: nodes depth first, nearest
/// first, then the exact distance of each triangle left to the core, less the radius. point_a
/// lies on A's triangle triangle_a, point_b on the shape's surface (triangle_b is -1); where
/// they meet (intersecting, distance 0) the search stops at the first triangle within the
/// shape, and both points are one point of that triangle inside the shape. No workspace, no
/// allocation. TooFewPoints for an empty mesh or shape, InvalidPose for a pose that is not
/// rigid, CapacityExceeded for a core of more than kMaxToolVertices vertices.
Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                     const Eigen::Isometry3d& pose_shape, MeshDistance& out);

/// The same, with the search seeded by the last answer's triangle (see ProximityCache): its
/// distance bounds the search from the root on. The distance is the cold one.
Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                     const Eigen::Isometry3d& pose_shape, ProximityCache& cache, MeshDistance& out);

/// How a convex tool touches a mesh (haptic rendering): the parts of the mesh's triangles
/// inside the tool, and how far the tool must move to push them all out.
struct MeshContact {
  bool intersecting = false;     ///< some triangle has a part inside the tool
  double penetration_depth = 0;  ///< how far the tool must move along the direction to clear them
  Eigen::Vector3d penetration_direction = Eigen::Vector3d::Zero();  ///< unit push-out direction (as Proximity's)
  Eigen::Vector3d point = Eigen::Vector3d::Zero();                  ///< the part's corner that needs it most
  int triangle = -1;                                                ///< the triangle of that corner
  double area = 0;                                                  ///< the parts' total area
  /// Their area-weighted centre (the contact force's point of application; continuous as the
  /// tool slides, as the direction is)
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  int tested = 0;                                                   ///< triangles that were clipped
  bool overflow = false;  ///< over kMaxContactTriangles overlapped: the first ones count
};

/// Most hull vertices a tool may have in mesh_contact (its fixed scratch space).
constexpr int kMaxToolVertices = 256;
/// Most overlapped triangles one mesh_contact call gathers (beyond: flagged, ignored).
constexpr int kMaxContactTriangles = 2048;

/// Contact of a convex tool (a shape prepared once in its own frame) with mesh A, each placed
/// in the world by its pose (the point and direction come back in the world frame). Each triangle whose box meets the
/// tool's box is clipped by the tool's face planes; the parts left are inside the tool. Their summed area vector
/// (triangle winding: counter-clockwise = outward) gives the push-out direction u, which turns continuously as the tool
/// slides over a tessellated surface; the depth is the largest distance, over the parts' corners p, that p travels
/// along -u inside the tool. A rounded tool (a sphere, a capsule, a radius on any shape): every
/// triangle within the radius of the core touches; u is their outward normals weighted by their
/// depths (radius less distance: each term vanishes as its triangle leaves, so u turns
/// continuously, and on a flat patch it is the patch's normal), the depth how far the tool moves
/// along u until they all lie a radius from the core (exact), the centre the core's nearest
/// points weighted as u, moved down to the surface along it; the area is 0.
/// No allocation. InvalidMesh if a tool without a radius is flat (a triangle: give it a radius),
/// CapacityExceeded for a tool (or a rounded tool's core) of more than kMaxToolVertices vertices;
/// the workspace is any made by make_workspace (its contact buffers are sized there; WorkspaceMismatch
/// for one that is not); TooFewPoints for an empty tool,
/// InvalidPose for a pose that is not rigid.
Status mesh_contact(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& tool,
                    const Eigen::Isometry3d& pose_tool, MeshWorkspace& ws, MeshContact& out);

/// When a convex tool moving within a tick (from pose t0 to t1, as time_of_impact moves a
/// shape: its origin along the segment, its rotation about one axis at a constant rate) first
/// touches mesh A, still at pose_a: the earliest time of impact over A's triangles, each by
/// time_of_impact's advancement (never after the first contact, within the tolerance at it),
/// and its triangle. The tool sweeps inside the capsule of its radius about its origin's
/// segment: only the nodes and triangles that capsule reaches before the earliest hit so far
/// are visited, and a triangle that a plane of the tool at that hit proves apart until then
/// is not advanced (it cannot make the answer late; under a face resting on a face, it would
/// only find the same time again). A rounded tool (a radius, a sphere, a capsule): its core
/// advances until it comes within the radius, and the tool's point lies on its surface.
/// Answers in the world frame; no allocation. `tolerance` 0: time_of_impact's
/// default over the tool and the mesh's box. TooFewPoints for an empty mesh or tool,
/// InvalidPose for a pose that is not rigid, InvalidArgument for a tolerance < 0 or NaN.
Status time_of_impact(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& tool,
                      const Eigen::Isometry3d& t0, const Eigen::Isometry3d& t1, TimeOfImpact& out, double tolerance = 0);

}  // namespace minksum
