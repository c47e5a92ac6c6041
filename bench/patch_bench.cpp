// Contact patches: minksum's contact_patch (the exact query, then the two supporting sets
// clipped to each other) against Bullet's polyhedral contact clipping (findSeparatingAxis, then
// clipHullAgainstHull), both from the shapes and two poses to the patch. The face-to-face
// families (tools::face_pairs: touching and pressed 1e-3, flat and rocking) along 1,024 poses,
// and the Table 1 pairs overlapping at 1,024 poses of B.
//   ContactPatch/<pair>/<touching|pressed|overlap>/<minksum|minksum_coherent|bullet_clip>
// (minksum_coherent: through one ProximityCache along the poses, which follow a slide.)
// Counter: points, the mean size of a patch (Bullet keeps the points of B's clipped face deeper
// than the margin; minksum the corners of the exact overlap).
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <memory>

#include "support/bullet_peer.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr int kPoses = 1024;
constexpr double kMargin = 1e-6;  // a patch of shapes within this of each other

// A box pair's boxes are box shapes (shape_from_box), as a caller with boxes prepares them.
Status shape_of(const std::vector<Vector3d>& points, const Box* box, ConvexShape& out) {
  return box ? shape_from_box(*box, out) : shape_from_points(points, out);
}

enum class Method { Cold, Coherent, Bullet };
constexpr Method kMethods[] = {Method::Cold, Method::Coherent, Method::Bullet};
const char* name(Method m) {
  return m == Method::Cold ? "minksum" : m == Method::Coherent ? "minksum_coherent" : "bullet_clip";
}

void Patch(benchmark::State& state, const std::vector<Vector3d>& a, const Box* box_a, const std::vector<Vector3d>& b,
           const Box* box_b, const std::vector<Isometry3d>& pose_b, Method method) {
  const bool bullet = method == Method::Bullet;
  ConvexShape A, B;
  if (shape_of(a, box_a, A) != Status::Ok || shape_of(b, box_b, B) != Status::Ok) {
    state.SkipWithError("shape");
    return;
  }
  const Isometry3d pose_a = Isometry3d::Identity();
  std::unique_ptr<peers::BulletClip> clip;
  if (bullet) clip = std::make_unique<peers::BulletClip>(A.polytope(), B.polytope());
  ContactPatch patch;
  ProximityCache cache;
  Vector3d normal;
  long points = 0, ticks = 0;
  for (auto _ : state) {
    const Isometry3d& pose = pose_b[ticks++ % kPoses];
    if (bullet) {
      points += clip->clip(pose_a, pose, kMargin, normal);
    } else {
      if (method == Method::Coherent)
        contact_patch(A, pose_a, B, pose, kMargin, cache, patch);
      else
        contact_patch(A, pose_a, B, pose, kMargin, patch);
      points += patch.size;
      benchmark::DoNotOptimize(patch.points[0]);
    }
  }
  state.counters["points"] = double(points) / double(std::max(1L, ticks));
  if (method == Method::Coherent)  // the share of patches the cache proved (box pairs need none)
    state.counters["warm_share"] = double(cache.warm) / double(std::max(1L, ticks));
}

const int registered = [] {
  static const std::vector<tools::FacePair> faces = tools::face_pairs();
  static std::vector<std::vector<Isometry3d>> poses;  // (kept: the benchmarks hold references)
  poses.reserve(faces.size() * 4 + 8);
  for (const auto& pair : faces)
    for (bool rocking : {false, true})
      for (const auto& [gap_name, gap] : {std::pair{"touching", 0.0}, std::pair{"pressed", -1e-3}}) {
        poses.emplace_back(kPoses);
        for (int k = 0; k < kPoses; ++k) poses.back()[k] = tools::face_pose(pair, k, kPoses, gap, rocking);
        for (Method method : kMethods)
          benchmark::RegisterBenchmark(
              ("ContactPatch/" + pair.name + (rocking ? "_rocking/" : "/") + gap_name + "/" + name(method)).c_str(),
              Patch, pair.a, pair.a_is_box ? &pair.box_a : nullptr, pair.b, pair.b_is_box ? &pair.box_b : nullptr,
              std::cref(poses.back()), method);
      }
  // Table 1's pairs overlapping: B moved about A's centre by up to a quarter of their size.
  static const std::vector<tools::Table1Pair> table1 = tools::table1_pairs();
  for (const auto& pair : table1) {
    poses.emplace_back(kPoses);
    for (int k = 0; k < kPoses; ++k) {
      const double t = 2 * M_PI * k / kPoses;
      poses.back()[k] = Eigen::Translation3d(0.25 * std::cos(t), 0.25 * std::sin(3 * t), 0.1 * std::sin(t)) *
                        Eigen::AngleAxisd(t, Vector3d(1, 2, 2).normalized());
    }
    for (Method method : kMethods)
      benchmark::RegisterBenchmark(("ContactPatch/" + pair.name + "/overlap/" + name(method)).c_str(), Patch, pair.a,
                                   nullptr, pair.b, nullptr, std::cref(poses.back()), method);
  }
  return 0;
}();

}  // namespace
