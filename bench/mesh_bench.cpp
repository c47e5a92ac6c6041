// Mesh-mesh distance (the paper's Section 5.1) against FCL 0.7's BVH distance (OBBRSS), on two
// copies of a Stanford bunny: MeshDistance/<mesh>/minksum|fcl_obbrss over the same 100 seeded
// poses (random rotation; centres 0.10 to 0.30 apart along a random direction, i.e. from
// overlapping through near contact to about two bunny lengths apart). Each iteration is one
// query; counters give the median per query and minksum's culling. MeshBuild/<mesh> times one
// octree build. MeshDistance/concentric_spheres/* is the octree's worst case: a sphere of 6,240
// triangles inside one of radius 1/0.9 times its own, nearly concentric (random rotation, centre
// offsets up to 1e-3), so that every triangle is about as near as any; max_us is its worst query.
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <random>

#include "fcl_peer.hpp"
#include "tools/mesh_io.hpp"

namespace {

using namespace minksum;

std::vector<Pose> bench_poses() {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Pose> poses(100);
  for (size_t k = 0; k < poses.size(); ++k) {
    poses[k].rotation = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    poses[k].translation = (0.10 + 0.20 * double(k) / double(poses.size())) * dir;
  }
  return poses;
}

const tools::Mesh& mesh(const std::string& name) {
  static std::map<std::string, tools::Mesh> cache;
  if (!cache.count(name)) {
    std::string source;
    cache[name] = name == "sphere_outer" ? tools::sphere_mesh(1.0, 40)
                  : name == "sphere_inner" ? tools::sphere_mesh(0.9, 40)
                                           : tools::demo_mesh(name, source);
  }
  return cache[name];
}

// A scene: mesh A, mesh B and B's poses.
struct Scene {
  std::string a, b;
};

std::vector<Pose> poses_of(const Scene& scene) {
  std::vector<Pose> poses = bench_poses();
  if (scene.a == "sphere_outer")
    for (Pose& p : poses) p.translation *= 1e-3 / 0.3;  // nearly concentric
  return poses;
}

void report_median(benchmark::State& state, std::vector<double>& us) {
  std::sort(us.begin(), us.end());
  state.counters["median_us"] = us[us.size() / 2];
  state.counters["max_us"] = us.back();
}

void Minksum(benchmark::State& state, Scene scene) {
  const tools::Mesh &ma = mesh(scene.a), &mb = mesh(scene.b);
  Octree A, B;
  build_octree(ma.vertices, ma.triangles, A);
  build_octree(mb.vertices, mb.triangles, B);
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  const auto poses = poses_of(scene);
  std::vector<double> us;
  double culled = 100, node_pairs = 0, triangle_pairs = 0;
  size_t k = 0;
  for (auto _ : state) {
    MeshDistance d;
    const auto t0 = std::chrono::steady_clock::now();
    mesh_distance(A, B, poses[k++ % poses.size()], ws, d);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    culled = std::min({culled, d.culled_percent_a, d.culled_percent_b});
    node_pairs += double(d.node_pairs), triangle_pairs += double(d.triangle_pairs);
  }
  report_median(state, us);
  state.counters["min_culled_pct"] = culled;
  state.counters["node_pairs"] = node_pairs / double(us.size());
  state.counters["triangle_pairs"] = triangle_pairs / double(us.size());
}

void Fcl(benchmark::State& state, Scene scene) {
  const tools::Mesh &ma = mesh(scene.a), &mb = mesh(scene.b);
  peers::FclMeshPair fcl(ma.vertices, ma.triangles, mb.vertices, mb.triangles);
  const auto poses = poses_of(scene);
  std::vector<double> us;
  size_t k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(fcl.distance(poses[k++ % poses.size()]));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  report_median(state, us);
}

void Build(benchmark::State& state, std::string name) {
  const tools::Mesh& m = mesh(name);
  for (auto _ : state) {
    Octree A;
    build_octree(m.vertices, m.triangles, A);
    state.counters["bytes"] = double(A.bytes());
  }
}

const int kRegistered = [] {
  for (auto [label, file] : {std::pair{"bunny_res2", "bun_zipper_res2.ply"}, std::pair{"bunny_full", "bun_zipper.ply"},
                             std::pair{"concentric_spheres", "sphere_outer"}}) {
    const std::string base = std::string("MeshDistance/") + label + "/";
    const Scene scene{file, label == std::string("concentric_spheres") ? "sphere_inner" : file};
    // At least the 100 poses once each.
    benchmark::RegisterBenchmark((base + "minksum").c_str(), Minksum, scene)->Unit(benchmark::kMicrosecond)->Iterations(300);
    benchmark::RegisterBenchmark((base + "fcl_obbrss").c_str(), Fcl, scene)->Unit(benchmark::kMicrosecond)->Iterations(300);
    benchmark::RegisterBenchmark((std::string("MeshBuild/") + label).c_str(), Build, file)->Unit(benchmark::kMillisecond);
  }
  return 0;
}();

}  // namespace
