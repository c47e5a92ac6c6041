// FCL 0.7 as a peer of the queries (benchmarks) and as an oracle (tests): its GJK (GST_INDEP)
// and libccd (GST_LIBCCD) solvers on boxes and convex polytopes, and its OBBRSS BVH distance on
// triangle meshes.
#pragma once

#include <minksum/mesh.hpp>

#include "support/peer_shape.hpp"

#include <Eigen/Geometry>

#include <array>
#include <memory>
#include <vector>

namespace minksum::peers {

/// FCL's two narrow-phase solvers.
enum class FclSolver { Gjk, Libccd };

/// What FCL answers for one pair.
struct FclAnswer {
  double distance = 0;               ///< FCL's min_distance (negative or 0 when it reports a collision)
  Eigen::Vector3d point_a, point_b;  ///< its nearest points
  bool collide = false;              ///< from fcl::collide
  double depth = 0;                  ///< penetration depth of the first contact
  Eigen::Vector3d normal;            ///< its contact normal (from A to B)
};

/// Two FCL objects built once; poses and queries per call, as a real FCL user does.
class FclPair {
 public:
  /// Two boxes (their poses are set here too).
  FclPair(const Box& a, const Box& b);
  /// A box and a triangle (a flat fcl::Convex: FCL has no distance for TriangleP), at their
  /// poses.
  FclPair(const Box& a, const Triangle& b);
  /// Two triangles (flat fcl::Convex).
  FclPair(const Triangle& a, const Triangle& b);
  /// Two convex polytopes (fcl::Convex), at the identity pose.
  FclPair(const ConvexPolytope& a, const ConvexPolytope& b);
  /// fcl::Sphere, fcl::Capsule, fcl::Box or fcl::Convex, at the identity pose. FCL 0.7 has no
  /// swept radius: a rounded box or polytope is its core (the caller subtracts the radius, as
  /// an FCL user would).
  FclPair(const PeerShape& a, const PeerShape& b);
  ~FclPair();
  /// Moves both objects (boxes: centre and rotation of each).
  void set_boxes(const Box& a, const Box& b);
  /// Places both objects by rigid poses.
  void set_poses(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);
  /// fcl::distance with the solver; nearest points too.
  double distance(FclSolver solver, FclAnswer* out = nullptr);
  /// fcl::collide with one contact: penetration depth and normal.
  bool penetration(FclSolver solver, FclAnswer& out);
  /// What minksum's proximity answers, from FCL: the distance with its nearest points, and on a
  /// collision (FCL's distance stops there) the penetration depth and normal too. The fair peer
  /// of a full proximity query.
  void proximity(FclSolver solver, FclAnswer& out);
  /// fcl::continuousCollide by conservative advancement (CCDC_CONSERVATIVE_ADVANCEMENT, its
  /// default toc_err 1e-4), A moving a0 -> a1 and B b0 -> b1: by translation (CCDM_TRANS), or
  /// turning (CCDM_LINEAR: the origin along the segment, the rotation about one axis at a
  /// constant rate). The time of contact (1: none) into `time`; whether they hit.
  bool time_of_impact(FclSolver solver, const Eigen::Isometry3d& a0, const Eigen::Isometry3d& a1,
                      const Eigen::Isometry3d& b0, const Eigen::Isometry3d& b1, bool turning, double& time);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Two triangle meshes as FCL BVH models with OBBRSS bounding volumes, built once.
class FclMeshPair {
 public:
  /// Builds both BVHs (FCL's default splitter).
  FclMeshPair(const std::vector<Eigen::Vector3d>& va, const std::vector<std::array<int, 3>>& ta,
              const std::vector<Eigen::Vector3d>& vb, const std::vector<std::array<int, 3>>& tb);
  ~FclMeshPair();
  /// fcl::distance with B placed by the pose (A at the identity), nearest points always computed
  /// (mesh_distance gives its witnesses); returned in A's frame when asked.
  double distance(const Eigen::Isometry3d& pose, Eigen::Vector3d* pa = nullptr, Eigen::Vector3d* pb = nullptr);
  /// Bytes of A's BVH: its nodes, vertices, triangles and primitive indices.
  size_t bytes_a() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A still triangle mesh (an OBBRSS BVH at the identity, built once) and a shape (a sphere, a
/// capsule, a box or a convex polytope; a swept radius is the caller's, as for FclPair).
class FclMeshShape {
 public:
  /// Builds the BVH (FCL's default splitter) and the shape.
  FclMeshShape(const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& t, const PeerShape& shape);
  ~FclMeshShape();
  /// fcl::distance with the shape at `pose` and the solver, nearest points always computed
  /// (mesh_distance gives its witnesses).
  double distance(FclSolver solver, const Eigen::Isometry3d& pose);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A still triangle mesh (an OBBRSS BVH at the identity, built once) and a moving box tool, for
/// continuous collision.
class FclMeshTool {
 public:
  /// The mesh's BVH (FCL's default splitter) and the box (centred at its pose's origin).
  FclMeshTool(const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& t,
              const Eigen::Vector3d& half_extents);
  ~FclMeshTool();
  /// fcl::continuousCollide of the box from t0 to t1 by FCL's naive solver: the motion sampled
  /// at num_max_iterations (10) poses, the first that collides (at or after the contact; a
  /// thin part between two samples is missed). FCL 0.7's conservative advancement reports no
  /// contact for a BVH (OBBRSS or RSS) against a shape or a mesh, even a box falling flat onto
  /// two triangles (FCL issues #120, #555). The time of contact (1: none) into `time`.
  bool time_of_impact(const Eigen::Isometry3d& t0, const Eigen::Isometry3d& t1, bool turning, double& time);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace minksum::peers
