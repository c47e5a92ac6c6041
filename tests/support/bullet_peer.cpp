#include "support/bullet_peer.hpp"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/NarrowPhaseCollision/btContinuousConvexCollision.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkEpaPenetrationDepthSolver.h>
#include <BulletCollision/NarrowPhaseCollision/btGjkPairDetector.h>
#include <BulletCollision/NarrowPhaseCollision/btPolyhedralContactClipping.h>
#include <BulletCollision/NarrowPhaseCollision/btSubSimplexConvexCast.h>
#include <BulletCollision/NarrowPhaseCollision/btPointCollector.h>
#include <BulletCollision/NarrowPhaseCollision/btVoronoiSimplexSolver.h>
#include <LinearMath/btConvexHullComputer.h>

namespace minksum::peers {

static_assert(sizeof(btScalar) == sizeof(double), "link Bullet's float64 libraries (BT_USE_DOUBLE_PRECISION)");

struct BulletPair::Impl {
  std::unique_ptr<btConvexShape> a, b;
  btVoronoiSimplexSolver simplex;
  btGjkEpaPenetrationDepthSolver epa;
  std::unique_ptr<btGjkPairDetector> gjk;
  void start(bool zero_margins = true) {
    if (zero_margins) a->setMargin(0), b->setMargin(0);  // exact shapes: no rounded margin
    gjk = std::make_unique<btGjkPairDetector>(a.get(), b.get(), &simplex, &epa);
  }
};

namespace {
btVector3 bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }

btTransform bt(const Eigen::Isometry3d& p) {
  const Eigen::Matrix3d& R = p.linear();
  return btTransform(btMatrix3x3(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2)),
                     bt(Eigen::Vector3d(p.translation())));
}

std::unique_ptr<btConvexShape> hull(const ConvexPolytope& p) {
  auto h = std::make_unique<btConvexHullShape>();
  for (const auto& v : p.vertices) h->addPoint(bt(v), false);
  h->recalcLocalAabb();
  return h;
}
}  // namespace

int bullet_hull(const std::vector<Eigen::Vector3d>& points) {
  // One computer per thread, reused as a user's loop would (its arrays keep their capacity).
  thread_local btConvexHullComputer computer;
  const btScalar shrink =
      computer.compute(points.data()->data(), int(sizeof(Eigen::Vector3d)), int(points.size()), 0, 0);
  return shrink < 0 ? -1 : computer.faces.size();
}

BulletPair::BulletPair(const Eigen::Vector3d& half_a, const Eigen::Vector3d& half_b) : impl_(std::make_unique<Impl>()) {
  impl_->a = std::make_unique<btBoxShape>(bt(half_a));
  impl_->b = std::make_unique<btBoxShape>(bt(half_b));
  impl_->start();
}

BulletPair::BulletPair(const ConvexPolytope& a, const ConvexPolytope& b) : impl_(std::make_unique<Impl>()) {
  impl_->a = hull(a), impl_->b = hull(b);
  impl_->start();
}

namespace {
std::unique_ptr<btConvexShape> rounded(const PeerShape& s) {
  std::unique_ptr<btConvexShape> shape;
  switch (s.kind) {
    case PeerShape::Kind::Sphere:
      return std::make_unique<btSphereShape>(s.radius);  // (its margin is its radius)
    case PeerShape::Kind::Capsule:
      return std::make_unique<btCapsuleShapeZ>(s.radius, 2 * s.half_length);
    case PeerShape::Kind::Box:
      shape = std::make_unique<btBoxShape>(bt(Eigen::Vector3d(s.half + Eigen::Vector3d::Constant(s.radius))));
      break;
    case PeerShape::Kind::Polytope:
      shape = hull(s.polytope);
      break;
  }
  shape->setMargin(s.radius);
  return shape;
}
}  // namespace

BulletPair::BulletPair(const PeerShape& a, const PeerShape& b) : impl_(std::make_unique<Impl>()) {
  impl_->a = rounded(a), impl_->b = rounded(b);
  impl_->start(false);
}

BulletPair::~BulletPair() = default;

double BulletPair::distance(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, BulletAnswer* out) {
  btDiscreteCollisionDetectorInterface::ClosestPointInput input;
  input.m_transformA = bt(a), input.m_transformB = bt(b);
  btPointCollector result;
  impl_->gjk->getClosestPoints(input, result, nullptr);
  if (out) {
    out->distance = result.m_distance;
    const btVector3 &p = result.m_pointInWorld, &n = result.m_normalOnBInWorld;
    out->point_b = Eigen::Vector3d(p.x(), p.y(), p.z()), out->normal = Eigen::Vector3d(n.x(), n.y(), n.z());
  }
  return result.m_distance;
}

struct BulletClip::Impl : btDiscreteCollisionDetectorInterface::Result {
  std::unique_ptr<btConvexHullShape> a, b;
  btVertexArray scratch1, scratch2;  // clipHullAgainstHull's buffers, kept between calls
  btAlignedObjectArray<btVector3> points;
  btAlignedObjectArray<btScalar> depths;
  void setShapeIdentifiersA(int, int) override {}
  void setShapeIdentifiersB(int, int) override {}
  void addContactPoint(const btVector3&, const btVector3& p, btScalar depth) override {
    points.push_back(p), depths.push_back(depth);
  }
};

BulletClip::BulletClip(const ConvexPolytope& a, const ConvexPolytope& b) : impl_(std::make_unique<Impl>()) {
  for (auto [shape, p] : {std::pair{&impl_->a, &a}, std::pair{&impl_->b, &b}}) {
    *shape = std::make_unique<btConvexHullShape>();
    for (const auto& v : p->vertices) (*shape)->addPoint(bt(v), false);
    (*shape)->recalcLocalAabb();
    (*shape)->setMargin(0);
    (*shape)->initializePolyhedralFeatures();
  }
}

BulletClip::~BulletClip() = default;

int BulletClip::clip(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b, double margin, Eigen::Vector3d& normal) {
  Impl& x = *impl_;
  x.points.resize(0), x.depths.resize(0);
  const btConvexPolyhedron &pa = *x.a->getConvexPolyhedron(), &pb = *x.b->getConvexPolyhedron();
  const btTransform ta = bt(a), tb = bt(b);
  btVector3 sep(0, 0, 1);
  btPolyhedralContactClipping::findSeparatingAxis(pa, pb, ta, tb, sep, x);
  btPolyhedralContactClipping::clipHullAgainstHull(sep, pa, pb, ta, tb, -1e30, margin, x.scratch1, x.scratch2, x);
  normal = Eigen::Vector3d(sep.x(), sep.y(), sep.z());
  return x.points.size();
}

void BulletClip::point(int k, Eigen::Vector3d& p, double& depth) const {
  const btVector3& q = impl_->points[k];
  p = Eigen::Vector3d(q.x(), q.y(), q.z()), depth = impl_->depths[k];
}

bool BulletPair::time_of_impact(const Eigen::Isometry3d& a0, const Eigen::Isometry3d& a1, const Eigen::Isometry3d& b0,
                                const Eigen::Isometry3d& b1, bool turning, double& time, Eigen::Vector3d& normal) {
  Impl& x = *impl_;
  btConvexCast::CastResult result;
  result.m_fraction = 1;  // (input: the farthest time asked for)
  bool hit;
  if (turning) {
    btContinuousConvexCollision cast(x.a.get(), x.b.get(), &x.simplex, &x.epa);
    hit = cast.calcTimeOfImpact(bt(a0), bt(a1), bt(b0), bt(b1), result);
  } else {
    btSubsimplexConvexCast cast(x.a.get(), x.b.get(), &x.simplex);
    hit = cast.calcTimeOfImpact(bt(a0), bt(a1), bt(b0), bt(b1), result);
  }
  time = hit ? result.m_fraction : 1.0;
  normal = Eigen::Vector3d(result.m_normal.x(), result.m_normal.y(), result.m_normal.z());
  return hit;
}

}  // namespace minksum::peers
