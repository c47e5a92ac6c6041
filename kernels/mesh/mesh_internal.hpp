// Shared internals of the mesh queries (octree.cpp, workspace.cpp, distance.cpp, contact.cpp).
#pragma once

#include <minksum/mesh.hpp>

#include "geometry/rigid.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace minksum::detail {

// Deepest level an octree may have (the bound of mesh_contact's stack; a cube 2^-20 of the
// root's is far below any leaf the adaptive rule keeps).
constexpr int kDepthCap = 20;

// What a MeshWorkspace holds: the search's node-pair heap and per-triangle marks, and
// mesh_contact's clipped parts, all sized by make_workspace.
struct MeshScratch {
  /// A node pair still to visit, with its squared distance bound.
  struct Entry {
    int a = 0, b = 0;   ///< node of A, node of B
    double bound2 = 0;  ///< lower bound of their squared distance
  };
  /// Node pairs still to visit: a heap of what it holds beyond 8 (depth_a + depth_b) + 16
  /// (make_workspace's heap_pairs), then that reserve for the depth-first fallback.
  std::vector<Entry> stack;
  std::vector<Eigen::Vector3d> moved_center;           ///< B's sphere centres in A's frame, on demand
  std::vector<unsigned> center_stamp;                  ///< query stamp per triangle of B
  std::vector<unsigned> seen_a, seen_b;                ///< query stamp per candidate triangle
  std::vector<int> near_b;                             ///< triangles of B's leaf near A's leaf
  std::vector<double> near_x, near_y, near_z, near_r;  ///< their spheres (A's frame)
  std::vector<double> near_lo;                         ///< their lowest corners along the leaves' line
  std::vector<double> proj_a, proj_b;                  ///< per leaf triangle: A's highest, B's lowest corner there
  std::vector<int> pass_a;                             ///< A's leaf triangles near B's leaf, nearest first
  std::vector<Eigen::Vector3d> near_corners;           ///< their corners (A's frame), three each
  std::vector<Eigen::Vector3d> near_normal;            ///< their unit normals (A's frame)
  std::vector<int> hits;                               ///< those near one triangle of A
  std::vector<Eigen::Vector3d> parts;                  ///< mesh_contact: corners of the parts inside
  std::vector<int> part_start;                         ///< mesh_contact: where each part's corners start
  unsigned stamp = 0;                                  ///< current query
};

// The node pairs of the search wait in a heap (kMeshHeapPairs by default), nearest bound first; past
// that it goes on depth first, where each split pops one pair and pushes at most 8: the stack
// never grows by more than 7 per level of the current path plus one (depth_reserve).
inline size_t depth_reserve(const Octree& a, const Octree& b) { return size_t(8 * (a.depth + b.depth) + 16); }

/// B's placement in A's frame, after both poses are checked: pose_b itself when A sits at the
/// identity (no rounding), else pose_a^-1 pose_b.
Status relative_pose(const Eigen::Isometry3d& pose_a, const Eigen::Isometry3d& pose_b, Rigid& out);

/// A point or segment core placed in the mesh's frame (s0 = s1 for a point), with the lower
/// bounds the mesh queries prune by.
struct PlacedSegment {
  Eigen::Vector3d s0, s1;
  /// Its point nearest x.
  Eigen::Vector3d nearest(const Eigen::Vector3d& x) const {
    const Eigen::Vector3d e = s1 - s0;
    const double len2 = e.squaredNorm();
    return len2 > 0 ? Eigen::Vector3d(s0 + std::clamp((x - s0).dot(e) / len2, 0.0, 1.0) * e) : s0;
  }
  /// Its highest value along u.
  double support(const Eigen::Vector3d& u) const { return std::max(u.dot(s0), u.dot(s1)); }
  /// A lower bound of its distance to the box (centre c, half extents h): their projections
  /// apart along the line from its point nearest c to c.
  double box_gap(const Eigen::Vector3d& c, const Eigen::Vector3d& h) const {
    const Eigen::Vector3d line = c - nearest(c);
    const double len = line.norm();
    if (!(len > 0)) return 0;
    const Eigen::Vector3d u = line / len;
    return u.dot(c) - u.cwiseAbs().dot(h) - support(u);
  }
};

/// |v| where its square leaves the doubles: a cross product of coordinates past 1e77 squares
/// past the largest double (the plain norm is inf), one of edges under 1e-77 below the smallest
/// (0). The plain norm where it is normal; else |v| scaled by its largest component first.
inline double norm_of(const Eigen::Vector3d& v) {
  const double n = v.norm();
  if (n > 0x1p-500 && n < 0x1p500) return n;
  const double m = v.cwiseAbs().maxCoeff();
  return m > 0 && m < std::numeric_limits<double>::infinity() ? m * (v / m).norm() : n;
}

/// The unit normal of a triangle (zero if it is degenerate).
inline Eigen::Vector3d unit_normal(const Eigen::Vector3d (&v)[3]) {
  const Eigen::Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]);
  const double len = norm_of(n);
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

}  // namespace minksum::detail
