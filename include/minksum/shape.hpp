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

/// An immutable convex shape in its body frame: a core swept by a ball of radius() (the core
/// (+) a ball: 0 for a plain polytope), and, built once, what the sums and queries need
/// (structure-of-arrays normals, edge directions and vertices; the Gauss map's adjacency). The
/// core is a polytope, a box, a triangle, a point (a sphere's) or a segment (a capsule's).
/// Copies share the same read-only data, so one shape may be used by many threads at once. A
/// default-constructed (or failed) shape is empty, and every call taking it returns
/// Status::TooFewPoints.
class ConvexShape {
 public:
  /// True until a builder succeeds.
  bool empty() const { return data_ == nullptr; }
  /// The core in the body frame: the support pairs (i, j) of sums and queries index its
  /// vertices. A sphere's core is its centre (one vertex, no edges or faces), a capsule's its
  /// segment (two vertices, no edges or faces).
  const ConvexPolytope& polytope() const;
  /// The radius of the ball swept around the core (0: the shape is its core).
  double radius() const { return radius_; }

 private:
  friend struct detail::ShapeAccess;
  std::shared_ptr<const detail::ShapeData> data_;
  double radius_ = 0;
};

/// The convex hull of a point set (polytope_from_points, then validated and prepared).
/// OutOfRange where a nonzero coordinate under 2^-300 (5e-91) of the largest leaves nearly
/// coplanar faces (kept apart by the exact hull) that the prepared Gauss map cannot tell apart.
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

/// A ball of `radius` about the body origin (a point core swept by the radius). InvalidArgument
/// for a radius that is not positive or not finite, OutOfRange for one beyond kMaxCoordinate or
/// under kMinExtent.
Status shape_from_sphere(double radius, ConvexShape& out);

/// A capsule along the body z axis: the segment from (0, 0, -half_length) to (0, 0, half_length)
/// swept by `radius` (FCL's and Coal's convention). A half_length of 0 gives the sphere of that
/// radius. InvalidArgument for a negative or non-finite half_length or a radius that is not
/// positive or not finite; OutOfRange for a half_length or radius beyond kMaxCoordinate, or a
/// radius (or a nonzero half_length) under kMinExtent.
Status shape_from_capsule(double half_length, double radius, ConvexShape& out);

/// `core` swept by a ball of `radius`: a rounded box, polytope or triangle (a swept triangle),
/// or a sphere or capsule with the radius added to theirs. O(1): it shares the core's prepared
/// data. TooFewPoints for an empty core, InvalidArgument for a negative or non-finite radius,
/// OutOfRange for a total radius beyond kMaxCoordinate.
Status shape_with_radius(const ConvexShape& core, double radius, ConvexShape& out);

/// Ok for a rigid pose: finite, translation within kMaxCoordinate, linear part a proper
/// rotation to kRotationTolerance (1e-9: no scale, shear or reflection); InvalidPose otherwise.
Status check_pose(const Eigen::Isometry3d& pose);

/// How far r is from a proper rotation: the largest entry of |R^T R - I|; infinity where det r
/// <= 0 or an entry is not finite. check_pose accepts up to kRotationTolerance.
double rotation_deviation(const Eigen::Matrix3d& r);

/// The proper rotation nearest r (its orthogonal polar factor, by Higham's iteration), for a
/// rotation stored in float or accumulated in products; r itself where it is not within 0.1 of a
/// rotation (rotation_deviation), which check_pose then refuses.
Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& r);

}  // namespace minksum
