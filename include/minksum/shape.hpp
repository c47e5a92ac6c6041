// minksum: prepared convex shapes, built and validated once, placed by a rigid pose per call
// (the convention of FCL, Coal and Drake: x_world = pose * x_body).
#pragma once

#include <minksum/model.hpp>

#include <Eigen/Geometry>
#include <memory>

namespace minksum {

namespace detail {
struct ShapeData;
struct ShapeAccess;
}  // namespace detail

/// An immutable convex shape in its body frame: the polytope and, built once, what the sums
/// and queries need (structure-of-arrays normals, edge directions and vertices; the Gauss map's
/// adjacency). Copies share the same read-only data, so one shape may be used by many threads
/// at once. A default-constructed (or failed) shape is empty, and every call taking it returns
/// Status::TooFewPoints.
class ConvexShape {
 public:
  /// True until a builder succeeds.
  bool empty() const { return data_ == nullptr; }
  /// The polytope in the body frame: the support pairs (i, j) of sums and queries index its
  /// vertices.
  const ConvexPolytope& polytope() const;

 private:
  friend struct detail::ShapeAccess;
  std::shared_ptr<const detail::ShapeData> data_;
};

/// The convex hull of a point set (polytope_from_points, then validated and prepared).
Status shape_from_points(const std::vector<Eigen::Vector3d>& points, ConvexShape& out);

/// A shape from an explicit convex mesh (polytope_from_mesh's checks).
Status shape_from_mesh(const std::vector<Eigen::Vector3d>& vertices, const std::vector<std::vector<int>>& faces,
                       ConvexShape& out);

/// A box (its corners in box_corner order), in the box's own frame as given.
Status shape_from_box(const Box& box, ConvexShape& out);

/// A triangle: a flat shape with vertices a, b, c.
Status shape_from_triangle(const Triangle& t, ConvexShape& out);

/// A shape from a polytope, validated: a closed 2-manifold with V - E + F = 2 (or a flat
/// polygon with its two sides), unit face normals, every edge listed with its two faces in
/// the Edge orientation, every vertex on its faces' planes, and convex at every edge.
/// InvalidMesh if not.
Status shape_from_polytope(const ConvexPolytope& p, ConvexShape& out);

/// Ok for a rigid pose: finite, translation within kMaxCoordinate, linear part a proper
/// rotation to 1e-9 (no scale, shear or reflection); InvalidPose otherwise.
Status check_pose(const Eigen::Isometry3d& pose);

}  // namespace minksum
