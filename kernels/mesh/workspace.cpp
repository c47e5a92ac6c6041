// The mesh queries' workspace, sized once per pair of octrees, and the relative pose they share.
#include "mesh/mesh_internal.hpp"

#include "core/validate.hpp"

#include <algorithm>
#include <memory>

namespace minksum {

using detail::depth_reserve;
using detail::MeshScratch;
using Eigen::Vector3d;

MeshWorkspace::MeshWorkspace() = default;
MeshWorkspace::MeshWorkspace(const MeshWorkspace& other)
    : scratch_(other.scratch_ ? std::make_unique<MeshScratch>(*other.scratch_) : nullptr) {}
MeshWorkspace::MeshWorkspace(MeshWorkspace&& other) noexcept = default;
MeshWorkspace& MeshWorkspace::operator=(const MeshWorkspace& other) {
  if (this != &other) scratch_ = other.scratch_ ? std::make_unique<MeshScratch>(*other.scratch_) : nullptr;
  return *this;
}
MeshWorkspace& MeshWorkspace::operator=(MeshWorkspace&& other) noexcept = default;
MeshWorkspace::~MeshWorkspace() = default;

void make_workspace(const Octree& a, const Octree& b, MeshWorkspace& workspace, int heap_pairs) {
  if (!workspace.scratch_) workspace.scratch_ = std::make_unique<MeshScratch>();
  MeshScratch& ws = *workspace.scratch_;
  ws.stack.assign(size_t(std::max(heap_pairs, 1)) + depth_reserve(a, b), MeshScratch::Entry{});
  ws.moved_center.assign(b.triangles.size(), Vector3d::Zero());
  ws.center_stamp.assign(b.triangles.size(), 0);
  ws.seen_a.assign(a.triangles.size(), 0);
  ws.seen_b.assign(b.triangles.size(), 0);
  for (auto* v : {&ws.near_b, &ws.hits}) v->assign(size_t(b.max_leaf), 0);
  for (auto* v : {&ws.near_x, &ws.near_y, &ws.near_z, &ws.near_r, &ws.near_lo, &ws.proj_b})
    v->assign(size_t(b.max_leaf), 0.0);
  ws.proj_a.assign(size_t(a.max_leaf), 0.0);
  ws.pass_a.assign(size_t(a.max_leaf), 0);
  ws.near_corners.assign(size_t(3 * b.max_leaf), Vector3d::Zero());
  ws.near_normal.assign(size_t(b.max_leaf), Vector3d::Zero());
  ws.parts.assign(size_t(8 * kMaxContactTriangles), Vector3d::Zero());
  ws.part_start.assign(size_t(kMaxContactTriangles + 1), 0);
  ws.stamp = 0;
}

namespace detail {

Status relative_pose(const Eigen::Isometry3d& pose_a, const Eigen::Isometry3d& pose_b, Rigid& out) {
  if (const Status s = check_pose(pose_a); s != Status::Ok) return s;
  if (const Status s = check_pose(pose_b); s != Status::Ok) return s;
  const bool identity = pose_a.linear() == Eigen::Matrix3d::Identity() && pose_a.translation() == Vector3d::Zero();
  out = Rigid(identity ? pose_b : Eigen::Isometry3d(pose_a.inverse(Eigen::Isometry) * pose_b));
  return Status::Ok;
}

}  // namespace detail

}  // namespace minksum
