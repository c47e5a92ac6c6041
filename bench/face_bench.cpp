// Face-to-face queries, the most common configuration of haptics and physics (a tool resting or
// sliding flat on a part): tools::face_pairs, B sliding over A's top face, 1e-3 of the size
// apart, exactly touching, or pressed 1e-3 into it, with or without a rocking of 1e-3 rad
// (family suffix _rocking). One query per iteration along 1,024 poses, the same for every
// method; minksum's boxes are shape_from_box shapes, as a user writes them.
//   FaceToFace/<family>/<apart|touching|pressed>/<minksum_cold|minksum_coherent|fcl_gjk|bullet_gjk_warm>
// Counters: searched_share (queries that needed the exhaustive search) and, for the coherent
// rows, warm_share. FCL's GJK answers its distance, Bullet its signed distance (EPA on
// contact) from its cached separating axis; minksum the distance, or the depth (Want::Witnesses).
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <memory>

#include "support/bullet_peer.hpp"
#include "support/fcl_peer.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr int kPoses = 1024;

enum class Method { Cold, Coherent, FclGjk, BulletWarm };

Status shape_of(const std::vector<Vector3d>& points, bool is_box, const Box& box, ConvexShape& out) {
  return is_box ? shape_from_box(box, out) : shape_from_points(points, out);
}

void FaceToFace(benchmark::State& state, const tools::FacePair& pair, double gap, bool rocking, Method method) {
  ConvexShape A, B;
  if (shape_of(pair.a, pair.a_is_box, pair.box_a, A) != Status::Ok ||
      shape_of(pair.b, pair.b_is_box, pair.box_b, B) != Status::Ok) {
    state.SkipWithError("shape");
    return;
  }
  // A at a generic pose, so that nothing is axis-aligned in the world.
  const Isometry3d pose_a(Eigen::Translation3d(0.3, -0.2, 0.1) *
                          Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));
  std::vector<Isometry3d> pose_b(kPoses);
  for (int k = 0; k < kPoses; ++k) pose_b[k] = pose_a * tools::face_pose(pair, k, kPoses, gap, rocking);
  std::unique_ptr<peers::FclPair> fcl;
  std::unique_ptr<peers::BulletPair> bullet;
  const bool boxes = pair.a_is_box && pair.b_is_box;
  if (method == Method::FclGjk)
    fcl = boxes ? std::make_unique<peers::FclPair>(pair.box_a, pair.box_b)
                : std::make_unique<peers::FclPair>(A.polytope(), B.polytope());
  if (method == Method::BulletWarm)
    bullet = boxes ? std::make_unique<peers::BulletPair>(pair.box_a.half_extents, pair.box_b.half_extents)
                   : std::make_unique<peers::BulletPair>(A.polytope(), B.polytope());
  // A box peer takes the box's own rotation in its pose.
  const auto box_pose = [&](const Isometry3d& pose, const Box& box) {
    Isometry3d x = pose;
    x.linear() = pose.linear() * box.rotation;
    return x;
  };
  Proximity p;
  ProximityCache cache;
  peers::FclAnswer answer;
  long searched = 0, ticks = 0;
  for (auto _ : state) {
    const int i = int(ticks++ % kPoses);
    switch (method) {
      case Method::Cold:
        proximity(A, pose_a, B, pose_b[i], p, Want::Witnesses), searched += p.searched;
        break;
      case Method::Coherent:
        proximity(A, pose_a, B, pose_b[i], cache, p, Want::Witnesses);
        break;
      case Method::FclGjk:
        if (boxes)
          fcl->set_poses(box_pose(pose_a, pair.box_a), box_pose(pose_b[i], pair.box_b));
        else
          fcl->set_poses(pose_a, pose_b[i]);
        fcl->proximity(peers::FclSolver::Gjk, answer);
        benchmark::DoNotOptimize(answer.distance);
        break;
      case Method::BulletWarm:
        benchmark::DoNotOptimize(boxes ? bullet->distance(box_pose(pose_a, pair.box_a), box_pose(pose_b[i], pair.box_b))
                                       : bullet->distance(pose_a, pose_b[i]));
        break;
    }
    benchmark::DoNotOptimize(p.distance);
  }
  if (method == Method::Coherent) {
    searched = cache.searched;
    state.counters["warm_share"] = double(cache.warm) / double(std::max(1L, cache.warm + cache.cold));
  }
  if (method == Method::Cold || method == Method::Coherent)
    state.counters["searched_share"] = double(searched) / double(std::max(1L, ticks));
}

const int registered = [] {
  static const std::vector<tools::FacePair> pairs = tools::face_pairs();
  const std::pair<const char*, double> gaps[] = {{"apart", 1e-3}, {"touching", 0.0}, {"pressed", -1e-3}};
  const std::pair<const char*, Method> methods[] = {{"minksum_cold", Method::Cold},
                                                    {"minksum_coherent", Method::Coherent},
                                                    {"fcl_gjk", Method::FclGjk},
                                                    {"bullet_gjk_warm", Method::BulletWarm}};
  for (const auto& pair : pairs)
    for (bool rocking : {false, true})
      for (const auto& [gap_name, gap] : gaps)
        for (const auto& [name, m] : methods)
          benchmark::RegisterBenchmark(
              ("FaceToFace/" + pair.name + (rocking ? "_rocking/" : "/") + gap_name + "/" + name).c_str(), FaceToFace,
              std::cref(pair), gap, rocking, m);
  return 0;
}();

}  // namespace
