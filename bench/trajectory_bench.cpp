// Queries along trajectories, where a haptics or physics loop runs them: seeded smooth relative
// motion (tools::trajectory: at most 1 % of the smaller object's size and 0.5 degree per tick,
// in and out of contact), the same poses for every method, one query per iteration (the
// trajectory repeats after 8,192 ticks, a single jump back).
//   Trajectory/box_box/<minksum_cold|minksum_coherent|fcl_gjk|bullet_gjk_warm>
//   Trajectory/<Table 1 pair|sphere64|sphere256>/<same methods>
//   Trajectory/bunny_full/<minksum_cold|minksum_coherent|fcl_obbrss|minksum_stale_cache>: a
//   20 x 16 x 12 mm box tool against the full bunny (exact mesh-mesh distance); the last row
//   seeds every query with the answer at the far side of the path (the seeded search's worst
//   case; that refill is not timed).
// minksum answers the distance, or the depth when they overlap (Want::Witnesses); FCL's GJK
// answers its distance (a negative or zero value on contact), Bullet its signed distance with
// EPA, from the detector's cached separating axis.
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <chrono>

#include "support/bullet_peer.hpp"
#include "support/fcl_peer.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr int kTicks = 8192;

enum class Method { Cold, Coherent, FclGjk, BulletWarm, FclObbrss, StaleCache };

// Counters: the fraction of ticks in contact, the share minksum's cache answered, and the
// share that needed the exhaustive search (searched: the cold rows' count).
void count(benchmark::State& state, long contacts, long ticks, const ProximityCache* cache, long searched = -1) {
  state.counters["contact_share"] = ticks ? double(contacts) / double(ticks) : 0;
  if (cache && cache->warm + cache->cold > 0)
    state.counters["warm_share"] = double(cache->warm) / double(cache->warm + cache->cold);
  if (cache) searched = cache->searched;
  if (searched >= 0 && ticks > 0) state.counters["searched_share"] = double(searched) / double(ticks);
}

// One query per iteration along a path of n poses by `method`: cold(i, out),
// coherent(i, cache, out), fcl(i) or bullet(i) for pose i.
template <class Cold, class Coherent, class Fcl, class Bullet>
void along(benchmark::State& state, Method method, size_t n, Cold cold, Coherent coherent, Fcl fcl, Bullet bullet) {
  Proximity p;
  ProximityCache cache;
  size_t k = 0;
  long contacts = 0, ticks = 0, searched = 0;
  for (auto _ : state) {
    const size_t i = k++ % n;
    switch (method) {
      case Method::Cold:
        cold(i, p), searched += p.searched;
        break;
      case Method::Coherent:
        coherent(i, cache, p);
        break;
      case Method::FclGjk:
        benchmark::DoNotOptimize(fcl(i));
        break;
      default:
        benchmark::DoNotOptimize(bullet(i));
        break;
    }
    benchmark::DoNotOptimize(p.distance);
    contacts += p.intersecting, ++ticks;
  }
  count(state, method <= Method::Coherent ? contacts : 0, ticks, method == Method::Coherent ? &cache : nullptr,
        method == Method::Cold ? searched : -1);
}

// Box A at a fixed pose; B's centre follows the trajectory around A's.
void BoxBox(benchmark::State& state, Method method) {
  Box a, body;
  a.half_extents = Vector3d(0.5, 0.35, 0.25), body.half_extents = Vector3d(0.3, 0.4, 0.2);
  a.rotation = tools::axis_angle(Vector3d(1, 2, 3), 0.4), a.center = Vector3d(0.1, -0.2, 0.3);
  const double smaller = 2 * body.half_extents.norm();
  const Isometry3d pose_a(Eigen::Translation3d(a.center) * Eigen::Quaterniond(a.rotation));
  const auto path = tools::trajectory(7, kTicks, 0.7, 1.6, 0.01 * smaller);
  std::vector<Box> b(path.size(), body);
  std::vector<Isometry3d> pose_b(path.size());
  for (size_t k = 0; k < path.size(); ++k) {
    pose_b[k] = pose_a * path[k];
    b[k].center = pose_b[k].translation(), b[k].rotation = pose_b[k].linear();
  }
  peers::FclPair fcl(a, b[0]);
  peers::FclAnswer answer;
  peers::BulletPair bullet(a.half_extents, body.half_extents);
  along(
      state, method, path.size(), [&](size_t i, Proximity& p) { proximity(a, b[i], p, Want::Witnesses); },
      [&](size_t i, ProximityCache& cache, Proximity& p) { proximity(a, b[i], cache, p, Want::Witnesses); },
      [&](size_t i) { return fcl.set_boxes(a, b[i]), fcl.proximity(peers::FclSolver::Gjk, answer), answer.distance; },
      [&](size_t i) { return bullet.distance(pose_a, pose_b[i]); });
}

// Two prepared shapes; B follows the trajectory around A.
void Shapes(benchmark::State& state, std::vector<Vector3d> pa, std::vector<Vector3d> pb, Method method) {
  ConvexShape A, B;
  if (shape_from_points(pa, A) != Status::Ok || shape_from_points(pb, B) != Status::Ok) {
    state.SkipWithError("shape");
    return;
  }
  // B's centre swings from 0.85 to 1.5 times the sum of their radii (shallow contact to
  // apart), 1 % of the smaller's diameter per tick.
  double ra = 0, rb = 0;
  for (const Vector3d& p : pa) ra = std::max(ra, p.norm());
  for (const Vector3d& p : pb) rb = std::max(rb, p.norm());
  const Isometry3d pose_a(Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.4, Vector3d::UnitY()));
  const auto path = tools::trajectory(11, kTicks, 0.85 * (ra + rb), 1.5 * (ra + rb), 0.02 * std::min(ra, rb));
  std::vector<Isometry3d> pose_b(path.size());
  for (size_t k = 0; k < path.size(); ++k) pose_b[k] = pose_a * path[k];
  peers::FclPair fcl(A.polytope(), B.polytope());
  peers::FclAnswer answer;
  peers::BulletPair bullet(A.polytope(), B.polytope());
  along(
      state, method, path.size(), [&](size_t i, Proximity& p) { proximity(A, pose_a, B, pose_b[i], p, Want::Witnesses); },
      [&](size_t i, ProximityCache& cache, Proximity& p) {
        proximity(A, pose_a, B, pose_b[i], cache, p, Want::Witnesses);
      },
      [&](size_t i) {
        return fcl.set_poses(pose_a, pose_b[i]), fcl.proximity(peers::FclSolver::Gjk, answer), answer.distance;
      },
      [&](size_t i) { return bullet.distance(pose_a, pose_b[i]); });
}

// The box tool of the haptics loop against the full bunny; the tool's centre swings between
// 30 and 120 mm from the bunny's bounding-box centre, 0.2 mm per tick at most (lengths for
// the Stanford bunny's 0.25 m bounding-box diagonal, scaled with the mesh's when it is another).
void BunnyFull(benchmark::State& state, Method method) {
  std::string source;
  const tools::Mesh scene = tools::demo_mesh("bun_zipper.ply", source);
  Vector3d lo = scene.vertices[0], hi = lo;
  for (const auto& v : scene.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double mm = (hi - lo).norm() / 0.25025 * 1e-3;
  tools::Mesh tool;
  for (const Vector3d& p : tools::cube_points())
    tool.vertices.emplace_back(10 * mm * p.x(), 8 * mm * p.y(), 6 * mm * p.z());
  ConvexShape hull;
  shape_from_points(tool.vertices, hull);
  tool.vertices = hull.polytope().vertices;
  for (const auto& f : hull.polytope().faces)
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) tool.triangles.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
  Octree A, B;
  OctreeOptions one_leaf;
  one_leaf.max_depth = 0;
  build_octree(scene.vertices, scene.triangles, A);
  build_octree(tool.vertices, tool.triangles, B, one_leaf);
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  const auto path = tools::trajectory(13, kTicks, 30 * mm, 120 * mm, 0.2 * mm);
  std::vector<Eigen::Isometry3d> poses(path.size());
  for (size_t k = 0; k < path.size(); ++k)
    poses[k].linear() = path[k].linear(), poses[k].translation() = (lo + hi) / 2 + path[k].translation();
  peers::FclMeshPair fcl(scene.vertices, scene.triangles, tool.vertices, tool.triangles);
  ProximityCache cache;
  MeshDistance d;
  size_t k = 0;
  long contacts = 0, ticks = 0;
  std::vector<double> us;
  us.reserve(size_t(1) << 20);
  using clock = std::chrono::steady_clock;
  MeshDistance far;
  for (auto _ : state) {
    const size_t i = k++ % poses.size();
    const Eigen::Isometry3d& pose = poses[i];
    if (method == Method::StaleCache) {  // a cache from the far side of the path: the seed misleads
      state.PauseTiming();
      mesh_distance(A, Eigen::Isometry3d::Identity(), B, poses[(i + poses.size() / 2) % poses.size()], ws, cache, far);
      state.ResumeTiming();
    }
    const auto t0 = clock::now();
    if (method == Method::Cold)
      mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, d);
    else if (method == Method::FclObbrss)
      benchmark::DoNotOptimize(fcl.distance(pose));
    else
      mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, cache, d);
    if (us.size() < us.capacity()) us.push_back(std::chrono::duration<double, std::micro>(clock::now() - t0).count());
    benchmark::DoNotOptimize(d.distance);
    contacts += d.intersecting, ++ticks;
  }
  count(state, method != Method::FclObbrss ? contacts : 0, ticks, method == Method::Coherent ? &cache : nullptr);
  // The median and worst single query (the mean is the benchmark's time).
  std::sort(us.begin(), us.end());
  if (!us.empty()) state.counters["median_us"] = us[us.size() / 2], state.counters["max_us"] = us.back();
}

const int registered = [] {
  const std::pair<const char*, Method> convex[] = {{"minksum_cold", Method::Cold},
                                                   {"minksum_coherent", Method::Coherent},
                                                   {"fcl_gjk", Method::FclGjk},
                                                   {"bullet_gjk_warm", Method::BulletWarm}};
  for (const auto& [name, m] : convex)
    benchmark::RegisterBenchmark((std::string("Trajectory/box_box/") + name).c_str(), BoxBox, m);
  std::vector<std::pair<std::string, std::pair<std::vector<Vector3d>, std::vector<Vector3d>>>> pairs;
  for (const auto& t : tools::table1_pairs()) pairs.push_back({t.name, {t.a, t.b}});
  pairs.push_back({"sphere64", {tools::sphere_points(64, 1), tools::sphere_points(64, 2)}});
  pairs.push_back({"sphere256", {tools::sphere_points(256, 3), tools::sphere_points(256, 4)}});
  for (const auto& [pair, points] : pairs)
    for (const auto& [name, m] : convex)
      benchmark::RegisterBenchmark(("Trajectory/" + pair + "/" + name).c_str(), Shapes, points.first, points.second, m);
  const std::pair<const char*, Method> mesh[] = {{"minksum_cold", Method::Cold},
                                                 {"minksum_coherent", Method::Coherent},
                                                 {"fcl_obbrss", Method::FclObbrss},
                                                 {"minksum_stale_cache", Method::StaleCache}};
  for (const auto& [name, m] : mesh)
    benchmark::RegisterBenchmark((std::string("Trajectory/bunny_full/") + name).c_str(), BunnyFull, m)
        ->Unit(benchmark::kMicrosecond);
  return 0;
}();

}  // namespace
