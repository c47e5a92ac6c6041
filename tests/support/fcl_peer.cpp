#include "support/fcl_peer.hpp"

#include <fcl/fcl.h>

namespace minksum::peers {

struct FclPair::Impl {
  std::shared_ptr<fcl::CollisionGeometryd> ga, gb;
  std::unique_ptr<fcl::CollisionObjectd> a, b;
};

namespace {
fcl::Transform3d pose(const Box& b) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = b.rotation;
  t.translation() = b.center;
  return t;
}

std::shared_ptr<fcl::Convexd> convex(const ConvexPolytope& p) {
  auto vertices = std::make_shared<std::vector<fcl::Vector3d>>(p.vertices.begin(), p.vertices.end());
  auto faces = std::make_shared<std::vector<int>>();  // count, then indices, per face
  for (const auto& f : p.faces) {
    faces->push_back(int(f.loop.size()));
    faces->insert(faces->end(), f.loop.begin(), f.loop.end());
  }
  return std::make_shared<fcl::Convexd>(vertices, int(p.faces.size()), faces, true);
}

fcl::GJKSolverType type(FclSolver s) { return s == FclSolver::Gjk ? fcl::GST_INDEP : fcl::GST_LIBCCD; }
}  // namespace

FclPair::FclPair(const Box& a, const Box& b) : impl_(std::make_unique<Impl>()) {
  impl_->ga = std::make_shared<fcl::Boxd>(2 * a.half_extents);
  impl_->gb = std::make_shared<fcl::Boxd>(2 * b.half_extents);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga, pose(a));
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb, pose(b));
}

namespace {
// FCL 0.7 has no distance for TriangleP against a box or a triangle ("not supported"): a
// triangle goes in as a flat Convex.
std::shared_ptr<fcl::Convexd> triangle(const Triangle& t) {
  ConvexPolytope flat;
  polytope_from_triangle(t, flat);
  return convex(flat);
}
}  // namespace

FclPair::FclPair(const Box& a, const Triangle& b) : impl_(std::make_unique<Impl>()) {
  impl_->ga = std::make_shared<fcl::Boxd>(2 * a.half_extents);
  impl_->gb = triangle(b);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga, pose(a));
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb);
}

FclPair::FclPair(const Triangle& a, const Triangle& b) : impl_(std::make_unique<Impl>()) {
  impl_->ga = triangle(a), impl_->gb = triangle(b);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga);
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb);
}

FclPair::FclPair(const ConvexPolytope& a, const ConvexPolytope& b) : impl_(std::make_unique<Impl>()) {
  impl_->ga = convex(a);
  impl_->gb = convex(b);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga);
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb);
}

namespace {
std::shared_ptr<fcl::CollisionGeometryd> geometry(const PeerShape& s) {
  switch (s.kind) {
    case PeerShape::Kind::Sphere:
      return std::make_shared<fcl::Sphered>(s.radius);
    case PeerShape::Kind::Capsule:
      return std::make_shared<fcl::Capsuled>(s.radius, 2 * s.half_length);
    case PeerShape::Kind::Box:
      return std::make_shared<fcl::Boxd>(2 * s.half);
    case PeerShape::Kind::Polytope:
      break;
  }
  return convex(s.polytope);
}
}  // namespace

FclPair::FclPair(const PeerShape& a, const PeerShape& b) : impl_(std::make_unique<Impl>()) {
  impl_->ga = geometry(a), impl_->gb = geometry(b);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga);
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb);
}

FclPair::~FclPair() = default;

void FclPair::set_boxes(const Box& a, const Box& b) {
  impl_->a->setTransform(pose(a));
  impl_->b->setTransform(pose(b));
}

void FclPair::set_poses(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  impl_->a->setTransform(fcl::Transform3d(a.matrix()));
  impl_->b->setTransform(fcl::Transform3d(b.matrix()));
}

double FclPair::distance(FclSolver solver, FclAnswer* out) {
  fcl::DistanceRequestd request(out != nullptr);
  request.gjk_solver_type = type(solver);
  fcl::DistanceResultd result;
  fcl::distance(impl_->a.get(), impl_->b.get(), request, result);
  if (out) {
    out->distance = result.min_distance;
    out->point_a = result.nearest_points[0];
    out->point_b = result.nearest_points[1];
  }
  return result.min_distance;
}

bool FclPair::penetration(FclSolver solver, FclAnswer& out) {
  fcl::CollisionRequestd request(1, true);
  request.gjk_solver_type = type(solver);
  fcl::CollisionResultd result;
  fcl::collide(impl_->a.get(), impl_->b.get(), request, result);
  out.collide = result.isCollision();
  if (out.collide) {
    out.depth = result.getContact(0).penetration_depth;
    out.normal = result.getContact(0).normal;
  }
  return out.collide;
}

void FclPair::proximity(FclSolver solver, FclAnswer& out) {
  out.collide = false, out.depth = 0;
  if (distance(solver, &out) <= 0) penetration(solver, out);
}

bool FclPair::time_of_impact(FclSolver solver, const Eigen::Isometry3d& a0, const Eigen::Isometry3d& a1,
                             const Eigen::Isometry3d& b0, const Eigen::Isometry3d& b1, bool turning, double& time) {
  fcl::ContinuousCollisionRequestd request;
  request.ccd_solver_type = fcl::CCDC_CONSERVATIVE_ADVANCEMENT;
  request.ccd_motion_type = turning ? fcl::CCDM_LINEAR : fcl::CCDM_TRANS;
  request.gjk_solver_type = type(solver);
  fcl::ContinuousCollisionResultd result;
  fcl::continuousCollide(impl_->ga.get(), fcl::Transform3d(a0.matrix()), fcl::Transform3d(a1.matrix()), impl_->gb.get(),
                         fcl::Transform3d(b0.matrix()), fcl::Transform3d(b1.matrix()), request, result);
  time = result.is_collide ? result.time_of_contact : 1.0;
  return result.is_collide;
}

struct FclMeshPair::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> ga, gb;
  std::unique_ptr<fcl::CollisionObjectd> a, b;
};

namespace {
std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh(const std::vector<Eigen::Vector3d>& v,
                                                 const std::vector<std::array<int, 3>>& t) {
  auto m = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  std::vector<fcl::Triangle> tris;
  for (const auto& x : t) tris.emplace_back(x[0], x[1], x[2]);
  m->beginModel();
  m->addSubModel(std::vector<fcl::Vector3d>(v.begin(), v.end()), tris);
  m->endModel();
  return m;
}
}  // namespace

FclMeshPair::FclMeshPair(const std::vector<Eigen::Vector3d>& va, const std::vector<std::array<int, 3>>& ta,
                         const std::vector<Eigen::Vector3d>& vb, const std::vector<std::array<int, 3>>& tb)
    : impl_(std::make_unique<Impl>()) {
  impl_->ga = bvh(va, ta), impl_->gb = bvh(vb, tb);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->ga);
  impl_->b = std::make_unique<fcl::CollisionObjectd>(impl_->gb);
}

FclMeshPair::~FclMeshPair() = default;

size_t FclMeshPair::bytes_a() const {
  // What BVHModel::memUsage adds up (in FCL 0.7 it returns BVH_OK, 0, not the sum), plus the
  // per-triangle primitive indices of the leaves.
  const auto& m = *impl_->ga;
  return size_t(m.getNumBVs()) * sizeof(fcl::BVNode<fcl::OBBRSSd>) +
         size_t(m.num_tris) * (sizeof(fcl::Triangle) + sizeof(unsigned)) +
         size_t(m.num_vertices) * sizeof(fcl::Vector3d) + sizeof(m);
}

double FclMeshPair::distance(const Eigen::Isometry3d& pose, Eigen::Vector3d* pa, Eigen::Vector3d* pb) {
  fcl::Transform3d t = fcl::Transform3d::Identity();
  t.linear() = pose.linear(), t.translation() = pose.translation();
  impl_->b->setTransform(t);
  fcl::DistanceRequestd request(true);  // nearest points always: mesh_distance gives its witnesses
  fcl::DistanceResultd result;
  fcl::distance(impl_->a.get(), impl_->b.get(), request, result);
  if (pa) *pa = result.nearest_points[0];
  if (pb) *pb = result.nearest_points[1];
  return result.min_distance;
}

struct FclMeshShape::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> mesh;
  std::unique_ptr<fcl::CollisionObjectd> a, b;
};

FclMeshShape::FclMeshShape(const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& t,
                           const PeerShape& shape)
    : impl_(std::make_unique<Impl>()) {
  impl_->mesh = bvh(v, t);
  impl_->a = std::make_unique<fcl::CollisionObjectd>(impl_->mesh);
  impl_->b = std::make_unique<fcl::CollisionObjectd>(geometry(shape));
}

FclMeshShape::~FclMeshShape() = default;

double FclMeshShape::distance(FclSolver solver, const Eigen::Isometry3d& pose) {
  impl_->b->setTransform(fcl::Transform3d(pose.matrix()));
  fcl::DistanceRequestd request(true);
  request.gjk_solver_type = type(solver);
  fcl::DistanceResultd result;
  fcl::distance(impl_->a.get(), impl_->b.get(), request, result);
  return result.min_distance;
}

struct FclMeshTool::Impl {
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> mesh;
  std::shared_ptr<fcl::Boxd> box;
};

FclMeshTool::FclMeshTool(const std::vector<Eigen::Vector3d>& v, const std::vector<std::array<int, 3>>& t,
                         const Eigen::Vector3d& half_extents)
    : impl_(std::make_unique<Impl>()) {
  impl_->mesh = bvh(v, t), impl_->box = std::make_shared<fcl::Boxd>(2 * half_extents);
}

FclMeshTool::~FclMeshTool() = default;

bool FclMeshTool::time_of_impact(const Eigen::Isometry3d& t0, const Eigen::Isometry3d& t1, bool turning,
                                 double& time) {
  fcl::ContinuousCollisionRequestd request;
  request.ccd_solver_type = fcl::CCDC_NAIVE;
  request.ccd_motion_type = turning ? fcl::CCDM_LINEAR : fcl::CCDM_TRANS;
  request.gjk_solver_type = fcl::GST_INDEP;
  fcl::ContinuousCollisionResultd result;
  const fcl::Transform3d still = fcl::Transform3d::Identity();
  fcl::continuousCollide(impl_->mesh.get(), still, still, impl_->box.get(), fcl::Transform3d(t0.matrix()),
                         fcl::Transform3d(t1.matrix()), request, result);
  time = result.is_collide ? result.time_of_contact : 1.0;
  return result.is_collide;
}

}  // namespace minksum::peers
