// Rounded shapes (spheres, capsules, a radius on a box) against FCL and Bullet: one proximity
// query per iteration along 1,024 poses of B gliding round A (see poses), apart (by 0.1, about
// a tenth of their size), touching (within 1e-12) or pressed (0.01 into each other).
//   Rounded/<pair>/<apart|touching|pressed>/<minksum|minksum_coherent|fcl_gjk|fcl_libccd|bullet>
// minksum answers the distance or the depth with witnesses (Want::Witnesses); FCL its distance
// and, on contact, its penetration (fcl::collide), with either solver (its sphere and capsule
// pairs take closed forms whatever the solver); Bullet its signed distance from its cached
// separating axis (EPA on contact), each radius its margin. FCL 0.7 has no swept radius: on a
// rounded box it answers for the cores, whose distance less the radii is the answer (a user's
// workaround, at the cost of the cores' query).
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "support/bullet_peer.hpp"
#include "support/fcl_peer.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr int kPoses = 1024;

enum class Method { Minksum, Coherent, FclGjk, FclLibccd, Bullet };

// One operand: the library's shape and the peers' description of it.
struct Operand {
  ConvexShape shape;
  peers::PeerShape peer;
};

Operand sphere() {
  Operand o;
  shape_from_sphere(0.5, o.shape);
  o.peer.kind = peers::PeerShape::Kind::Sphere, o.peer.radius = 0.5;
  return o;
}

Operand capsule() {
  Operand o;
  shape_from_capsule(0.6, 0.3, o.shape);
  o.peer.kind = peers::PeerShape::Kind::Capsule, o.peer.radius = 0.3, o.peer.half_length = 0.6;
  return o;
}

Operand box(double radius) {
  Operand o;
  Box b;
  b.half_extents = Vector3d(0.5, 0.4, 0.3);
  ConvexShape core;
  shape_from_box(b, core);
  shape_with_radius(core, radius, o.shape);
  o.peer.kind = peers::PeerShape::Kind::Box, o.peer.half = b.half_extents, o.peer.radius = radius;
  return o;
}

Operand polytope() {  // an icosahedron of radius about 0.5
  Operand o;
  shape_from_points(tools::scaled(tools::icosahedron_points(), 0.5), o.shape);
  o.peer.kind = peers::PeerShape::Kind::Polytope, o.peer.polytope = o.shape.polytope();
  return o;
}

struct Pair {
  std::string name;
  Operand a, b;
};

std::vector<Pair> pairs() {
  return {{"sphere_sphere", sphere(), sphere()},        {"sphere_box", sphere(), box(0)},
          {"sphere_polytope", sphere(), polytope()},    {"capsule_capsule", capsule(), capsule()},
          {"capsule_box", capsule(), box(0)},           {"capsule_polytope", capsule(), polytope()},
          {"rounded_box_rounded_box", box(0.1), box(0.1)}};
}

// The signed distance of the pair at B's pose.
double signed_distance(const Pair& p, const Isometry3d& pose_b) {
  Proximity x;
  proximity(p.a.shape, Isometry3d::Identity(), p.b.shape, pose_b, x, Want::Distance);
  return x.intersecting ? -x.penetration_depth : x.distance;
}

// A coherent path of B about A: its direction from A turns by 0.01 rad per pose about a slowly
// turning axis, B itself by 0.005 rad, and along the direction B sits where the signed distance
// is `gap` (secant steps from the last pose's distance: the distance along a line from A's
// centre grows with it beyond contact). All directions and orientations come round.
std::vector<Isometry3d> poses(const Pair& p, double gap) {
  std::mt19937_64 rng(56);
  std::normal_distribution<double> g;
  const auto random_unit = [&] { return Vector3d(g(rng), g(rng), g(rng)).normalized(); };
  Vector3d u = random_unit(), axis = random_unit(), spin = random_unit();
  const Vector3d wobble = random_unit();
  Eigen::Matrix3d turn = Eigen::Quaterniond(g(rng), g(rng), g(rng), g(rng)).normalized().toRotationMatrix();
  std::vector<Isometry3d> out;
  double t = 3;
  while (int(out.size()) < kPoses) {
    u = Eigen::AngleAxisd(0.01, axis) * u, axis = Eigen::AngleAxisd(0.003, wobble) * axis;
    turn = Eigen::AngleAxisd(0.005, spin) * turn;
    Isometry3d pose = Isometry3d::Identity();
    pose.linear() = turn;
    for (int k = 0; k < 60; ++k) {
      pose.translation() = t * u;
      const double s = signed_distance(p, pose);
      if (std::abs(s - gap) <= 1e-12) break;
      t += gap - s;
    }
    if (std::abs(signed_distance(p, pose) - gap) <= 1e-12) out.push_back(pose);
  }
  return out;
}

void Rounded(benchmark::State& state, const Pair& pair, double gap, Method method) {
  const std::vector<Isometry3d> pose_b = poses(pair, gap);
  const Isometry3d id = Isometry3d::Identity();
  std::unique_ptr<peers::FclPair> fcl;
  std::unique_ptr<peers::BulletPair> bullet;
  if (method == Method::FclGjk || method == Method::FclLibccd)
    fcl = std::make_unique<peers::FclPair>(pair.a.peer, pair.b.peer);
  if (method == Method::Bullet) bullet = std::make_unique<peers::BulletPair>(pair.a.peer, pair.b.peer);
  Proximity p;
  ProximityCache cache;
  peers::FclAnswer answer;
  long ticks = 0;
  for (auto _ : state) {
    const Isometry3d& pose = pose_b[size_t(ticks++ % kPoses)];
    switch (method) {
      case Method::Minksum:
        proximity(pair.a.shape, id, pair.b.shape, pose, p, Want::Witnesses);
        break;
      case Method::Coherent:
        proximity(pair.a.shape, id, pair.b.shape, pose, cache, p, Want::Witnesses);
        break;
      case Method::FclGjk:
      case Method::FclLibccd:
        fcl->set_poses(id, pose);
        fcl->proximity(method == Method::FclGjk ? peers::FclSolver::Gjk : peers::FclSolver::Libccd, answer);
        benchmark::DoNotOptimize(answer.distance);
        break;
      case Method::Bullet:
        benchmark::DoNotOptimize(bullet->distance(id, pose));
        break;
    }
    benchmark::DoNotOptimize(p.distance);
  }
  if (method == Method::Coherent)
    state.counters["warm_share"] = double(cache.warm) / double(std::max(1L, cache.warm + cache.cold));
}

const int registered = [] {
  static const std::vector<Pair> all = pairs();
  const std::pair<const char*, double> gaps[] = {{"apart", 0.1}, {"touching", 0.0}, {"pressed", -0.01}};
  const std::pair<const char*, Method> methods[] = {{"minksum", Method::Minksum},
                                                    {"minksum_coherent", Method::Coherent},
                                                    {"fcl_gjk", Method::FclGjk},
                                                    {"fcl_libccd", Method::FclLibccd},
                                                    {"bullet", Method::Bullet}};
  for (const auto& pair : all)
    for (const auto& [gap_name, gap] : gaps)
      for (const auto& [name, m] : methods)
        benchmark::RegisterBenchmark(("Rounded/" + pair.name + "/" + gap_name + "/" + name).c_str(), Rounded,
                                     std::cref(pair), gap, m);
  return 0;
}();

}  // namespace
