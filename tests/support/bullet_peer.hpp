// Bullet 3 (Debian's float64 libraries) as the warm-started peer of the coherent queries:
// btGjkPairDetector with a btVoronoiSimplexSolver keeps its cached separating axis from one
// call to the next, and btGjkEpaPenetrationDepthSolver answers overlapping poses.
#pragma once

#include <minksum/model.hpp>

#include "support/peer_shape.hpp"

#include <Eigen/Geometry>
#include <memory>
#include <vector>

namespace minksum::peers {

/// btConvexHullComputer (Bullet's exact-integer hull, Preparata & Hong, planar n-gon faces) on
/// the points; returns its face count, or -1 if it fails.
int bullet_hull(const std::vector<Eigen::Vector3d>& points);

/// Bullet's answer for one pose.
struct BulletAnswer {
  double distance = 0;                                ///< signed: negative is the penetration depth
  Eigen::Vector3d point_b = Eigen::Vector3d::Zero();  ///< its nearest (deepest) point on B
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();   ///< unit normal on B, towards A
};

/// Two Bullet convex shapes with zero margin and one pair detector, built once; poses per
/// call, as a Bullet user running a loop does (the detector stays warm between calls).
class BulletPair {
 public:
  /// Two boxes (btBoxShape), given by their half extents in their own frames.
  BulletPair(const Eigen::Vector3d& half_a, const Eigen::Vector3d& half_b);
  /// Two convex polytopes (btConvexHullShape of their vertices).
  BulletPair(const ConvexPolytope& a, const ConvexPolytope& b);
  /// btSphereShape, btCapsuleShapeZ, btBoxShape or btConvexHullShape, a radius as Bullet's
  /// margin (a box's half extents grown by it: Bullet's box holds its margin inside).
  BulletPair(const PeerShape& a, const PeerShape& b);
  ~BulletPair();
  /// The signed distance at the poses, from the detector's last separating axis.
  double distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, BulletAnswer* out = nullptr);
  /// The time of impact of A moving a0 -> a1 and B b0 -> b1 within a tick: for a pure
  /// translation btSubsimplexConvexCast (van den Bergen's GJK ray cast, what Bullet's own
  /// convex sweeps use; its btGjkConvexCast reports no hit for a box falling flat onto a box
  /// with zero margins), and btContinuousConvexCollision (conservative advancement on GJK
  /// distances, stopping within 1e-3, absolute) when either turns. Whether they hit, the time
  /// in [0, 1] (1: no hit), its normal.
  bool time_of_impact(const Eigen::Isometry3d& a0, const Eigen::Isometry3d& a1, const Eigen::Isometry3d& b0,
                      const Eigen::Isometry3d& b1, bool turning, double& time, Eigen::Vector3d& normal);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Bullet's contact manifold of two convex polyhedra (btConvexHullShape with its polyhedral
/// features, faces merged by btConvexHullComputer): btPolyhedralContactClipping's
/// findSeparatingAxis (the SAT over face normals and edge pairs), then clipHullAgainstHull
/// (B's face most opposed to the axis clipped by A's side planes, O(n_A n_B)), as its
/// btConvexConvexAlgorithm does for polyhedral shapes.
class BulletClip {
 public:
  /// The two polytopes, prepared once.
  BulletClip(const ConvexPolytope& a, const ConvexPolytope& b);
  ~BulletClip();
  /// The contact points at the poses, deeper than -margin: their count (the last call's
  /// points and depths are kept), the separating normal from A towards B into `normal`.
  int clip(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double margin, Eigen::Vector3d& normal);
  /// Point k of the last call (on B, world frame) and its depth (negative: penetrating).
  void point(int k, Eigen::Vector3d& p, double& depth) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace minksum::peers
