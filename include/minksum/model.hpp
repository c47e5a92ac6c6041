// minksum: value types of the model (boxes, triangles, convex polytopes) and the status codes.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace minksum {

/// Outcome of every fallible call; the library never throws.
enum class Status {
  Ok = 0,
  NonFinite,         ///< an input coordinate is NaN or Inf
  TooFewPoints,      ///< fewer than 3 distinct points
  Collinear,         ///< all points lie on one line (a segment is not a polytope)
  InvalidMesh,       ///< bad index, face with < 3 vertices, open or non-manifold explicit mesh
  NotConvex,         ///< an explicit mesh is not convex (or a face is not planar)
  InvalidBox,        ///< a box half extent is <= 0 or its rotation is not a rotation
  DegenerateResult,  ///< the sum is not a solid (two coplanar flat operands without a radius)
  HullFailed,        ///< the convex hull could not be built from input that passed validation
  OutOfRange,        ///< a coordinate's magnitude exceeds kMaxCoordinate, a shape is under kMinExtent across, or (prepared shapes) its coordinates span more than 2^300 where that matters
  InvalidPose,       ///< a pose that is not a finite rigid motion (scale, shear, reflection, NaN)
  InvalidArgument,   ///< a number outside its documented range (a negative or NaN margin)
  CapacityExceeded,  ///< a result larger than its fixed capacity (a contact patch's 128 points)
  Unsupported,       ///< an operation that does not take this kind of shape yet (see its comment)
  EmptyMesh,         ///< a mesh without triangles, or a point cloud without points
  WorkspaceMismatch, ///< a MeshWorkspace not made (make_workspace) for the meshes of the call
};

/// Largest coordinate magnitude accepted: products of three stay finite in double, so the
/// exact predicates and the distances never meet an overflow.
constexpr double kMaxCoordinate = 1e100;
/// How far a pose's (or a box's) rotation R may be from a proper rotation: every entry of
/// R^T R - I (rotation_deviation) within it, and det R > 0.
constexpr double kRotationTolerance = 1e-9;
/// Smallest extent (bounding-box diagonal) of a shape built from points or a mesh: squares and
/// cubes of its lengths stay normal doubles, so no test of its shape underflows to zero.
constexpr double kMinExtent = 1e-100;

/// Human-readable one-line description of a status.
const char* to_string(Status s);

/// Oriented box: the points center + rotation * (s .* half_extents) for s in [-1, 1]^3.
struct Box {
  Eigen::Vector3d center = Eigen::Vector3d::Zero();             ///< world position of the centre
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();       ///< columns are the box axes
  Eigen::Vector3d half_extents = Eigen::Vector3d::Constant(1);  ///< half side lengths (> 0)
};

/// Triangle with vertices a, b, c.
struct Triangle {
  Eigen::Vector3d a = Eigen::Vector3d::Zero();  ///< first corner
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  ///< second corner
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  ///< third corner
};

/// One polygonal face: a vertex loop counter-clockwise seen from outside, and its plane.
struct Face {
  std::vector<int> loop;                             ///< vertex indices, counter-clockwise seen from outside
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  ///< outward unit normal
  double offset = 0;                                 ///< plane: normal . x = offset
};

/// One undirected edge with its two adjacent faces; `left` walks v0 -> v1 in its loop.
struct Edge {
  int v0 = -1, v1 = -1;       ///< endpoint vertex indices
  int left = -1, right = -1;  ///< face whose loop has v0 -> v1, and face whose loop has v1 -> v0
};

/// Convex polytope: vertices, polygonal faces (coplanar triangles merged) and unique edges.
/// A flat polytope (a triangle, a polygon) has exactly two faces, its two sides.
struct ConvexPolytope {
  std::vector<Eigen::Vector3d> vertices;  ///< extreme points only
  std::vector<Face> faces;                ///< polygonal faces
  std::vector<Edge> edges;                ///< each edge once
  std::vector<int> input_index;           ///< vertices[k] was input point input_index[k]
  bool flat = false;                      ///< true for a polygon (two faces, zero volume)
};

/// The exact convex hull of a point set (exactly coplanar facets merged). Duplicates are dropped;
/// points within 64 eps of the size of a plane give a flat polytope (farther off, a thin solid);
/// fewer than 3 distinct or collinear points are rejected.
Status polytope_from_points(const std::vector<Eigen::Vector3d>& points, ConvexPolytope& out);

/// A convex polytope from an explicit mesh (faces as vertex loops, any orientation).
/// Validated: closed 2-manifold, planar convex faces, every vertex below every face plane.
Status polytope_from_mesh(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::vector<int>>& faces,
                          ConvexPolytope& out);

/// Ok for a valid box: finite, coordinates within kMaxCoordinate, half extents above 1e-13 of
/// its largest coordinate (else its corners coincide in double), rotation a proper rotation
/// (to 1e-9).
Status check_box(const Box& box);

/// Ok for a valid triangle: finite, coordinates within kMaxCoordinate, three distinct corners
/// (TooFewPoints) that are not collinear (Collinear, 1e-12 of its diagonal).
Status check_triangle(const Triangle& t);

/// Corner `code` of the box: bit a of code set means the +h_a side of axis a.
Eigen::Vector3d box_corner(const Box& box, int code);

/// The box as a polytope; vertex k is the corner with bit a of k set iff its axis-a sign is +.
Status polytope_from_box(const Box& box, ConvexPolytope& out);

/// The triangle as a flat polytope with vertices a, b, c (indices 0, 1, 2).
Status polytope_from_triangle(const Triangle& t, ConvexPolytope& out);

/// Support function h(n) = max over vertices of n . v, with the index of a maximiser.
double support(const ConvexPolytope& p, const Eigen::Vector3d& n, int* argmax = nullptr);

}  // namespace minksum
