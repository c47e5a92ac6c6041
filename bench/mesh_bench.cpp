// Mesh-mesh distance (the paper's Section 5.1) against FCL 0.7's BVH distance (OBBRSS), on two
// copies of a Stanford bunny: MeshDistance/<mesh>/minksum|fcl_obbrss over the same 100 seeded
// poses (random rotation; centres 0.10 to 0.30 apart along a random direction, i.e. from
// overlapping through near contact to about two bunny lengths apart). Each iteration is one
// query; counters give the median per query and minksum's culling. MeshBuild/<mesh> times one
// octree build. MeshDistance/concentric_spheres/* is the octree's worst case: a sphere of 6,240
// triangles inside one of radius 1/0.9 times its own, nearly concentric (random rotation, centre
// offsets up to 1e-3), so that every triangle is about as near as any; max_us is its worst query.
//
// MeshDistance/<pair>/minksum|fcl_obbrss over banded poses (tools::banded_poses, seeded): the
// bunny against itself and pairs of libcgal-demo meshes of other shapes (each scaled to a unit
// bounding-box diagonal), 99 poses: 33 intersecting, 33 apart by less than 5 % of the smaller
// mesh's diagonal (the near band, where haptics lives), 33 farther, each pose run 3 times (its
// fastest counts). Counters per band: median and worst us, minksum's median culled percentage;
// bytes per triangle of each structure. Two generated thin shapes, each against itself:
// "ribbon", a twisted helical ribbon of 8,000 slivers (tools::ribbon_mesh: 25 to 1), and
// "flattened", a closed surface of 14,160 triangles flattened to 1:200 (tools::flattened_mesh),
// and "flattened_tilted", the same turned off the coordinate axes (tools::tilted): FCL's
// oriented boxes do not care, boxes aligned with the mesh's axes do.
//
// MeshShapeDistance/<sphere|capsule>_bunny_full/minksum|fcl_obbrss_gjk|fcl_obbrss_libccd: a 5 mm
// sphere and a capsule (10 mm half length, 4 mm radius) against the full bunny, 99 banded poses
// by the tool's 20 mm size (tools::banded_poses' shape form), each run 3 times; FCL's sphere and
// capsule against its OBBRSS BVH with either solver.
//
// PointDistance/<pair>/minksum|nanoflann: clouds sampled from the same meshes' surfaces (50K to
// 200K points), the same banded poses; the exact closest pair of points, both structures built
// beforehand (PointBuild/<cloud>/minksum|nanoflann times the builds, with bytes per point).
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <random>
#include <tuple>

#include "support/fcl_peer.hpp"
#include "support/nanoflann_peer.hpp"
#include "support/mesh_io.hpp"

namespace {

using namespace minksum;

std::vector<Eigen::Isometry3d> bench_poses() {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Eigen::Isometry3d> poses(100);
  for (size_t k = 0; k < poses.size(); ++k) {
    poses[k].linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    poses[k].translation() = (0.10 + 0.20 * double(k) / double(poses.size())) * dir;
  }
  return poses;
}

const tools::Mesh& mesh(const std::string& name) {
  static std::map<std::string, tools::Mesh> cache;
  if (!cache.count(name)) {
    std::string source;
    tools::Mesh& m = cache[name];
    if (name == "sphere_outer")
      m = tools::sphere_mesh(1.0, 40);
    else if (name == "ribbon")
      m = tools::ribbon_mesh(4000, 8);
    else if (name == "flattened")
      m = tools::flattened_mesh(60);
    else if (name == "flattened_tilted")
      m = tools::tilted(tools::flattened_mesh(60));
    else if (name == "sphere_inner")
      m = tools::sphere_mesh(0.9, 40);
    else if (name.find(".off") == std::string::npos || !tools::cgal_demo_mesh(name, m))
      m = tools::demo_mesh(name, source);
  }
  return cache[name];
}

double diagonal(const tools::Mesh& m) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = -lo;
  for (const auto& t : m.triangles)
    for (int k : t) lo = lo.cwiseMin(m.vertices[size_t(k)]), hi = hi.cwiseMax(m.vertices[size_t(k)]);
  return (hi - lo).norm();
}

// A scene: mesh A, mesh B and B's poses.
struct Scene {
  std::string a, b;
  bool banded = false;  ///< banded_poses, not bench_poses
};

constexpr int kBandedPoses = 99;

std::vector<Eigen::Isometry3d> poses_of(const Scene& scene) {
  if (scene.banded) {  // the same poses for both methods: built once per scene
    static std::map<std::string, std::vector<Eigen::Isometry3d>> cache;
    std::vector<Eigen::Isometry3d>& poses = cache[scene.a + "|" + scene.b];
    if (poses.empty()) {
      const tools::Mesh &ma = mesh(scene.a), &mb = mesh(scene.b);
      Octree A, B;
      build_octree(ma.vertices, ma.triangles, A);
      build_octree(mb.vertices, mb.triangles, B);
      poses = tools::banded_poses(A, B, std::min(diagonal(ma), diagonal(mb)), 2026, kBandedPoses);
    }
    return poses;
  }
  std::vector<Eigen::Isometry3d> poses = bench_poses();
  if (scene.a == "sphere_outer")
    for (Eigen::Isometry3d& p : poses) p.translation() *= 1e-3 / 0.3;  // nearly concentric
  return poses;
}

double median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x.empty() ? 0.0 : x[x.size() / 2];
}

// us[k]: the time of the k-th query, pose k % poses; culled[k] its least culled percentage.
// Banded scenes: each pose counts with the fastest of its runs (the machine is shared: a
// single preempted run would otherwise be a pose's "worst"), then median and worst per band.
void report(benchmark::State& state, const Scene& scene, const std::vector<double>& us,
            const std::vector<double>& culled) {
  if (!scene.banded) {
    state.counters["median_us"] = median(us);
    state.counters["max_us"] = *std::max_element(us.begin(), us.end());
    return;
  }
  std::vector<double> pose_us(kBandedPoses, 1e300), pose_culled(kBandedPoses, 0);
  for (size_t k = 0; k < us.size(); ++k) {
    pose_us[k % kBandedPoses] = std::min(pose_us[k % kBandedPoses], us[k]);
    if (!culled.empty()) pose_culled[k % kBandedPoses] = culled[k];
  }
  state.counters["median_us"] = median(pose_us);
  state.counters["max_us"] = *std::max_element(pose_us.begin(), pose_us.end());
  for (int band = 0; band < 3; ++band) {
    std::vector<double> t, c;
    for (int p = 0; p < kBandedPoses; ++p)
      if (tools::band_of(p, kBandedPoses) == band) t.push_back(pose_us[size_t(p)]), c.push_back(pose_culled[size_t(p)]);
    const std::string name = band == 0 ? "contact" : band == 1 ? "near" : "far";
    state.counters[name + "_median_us"] = median(t);
    state.counters[name + "_max_us"] = *std::max_element(t.begin(), t.end());
    if (!culled.empty()) state.counters[name + "_culled_pct"] = median(c);
  }
}

// The timed queries of minksum between two built octrees, and their counters.
void run_minksum(benchmark::State& state, const Octree& A, const Octree& B, const Scene& scene) {
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  const auto poses = poses_of(scene);
  std::vector<double> us, culled;
  double node_pairs = 0, leaf_pairs = 0, triangle_pairs = 0;
  size_t k = 0;
  for (auto _ : state) {
    MeshDistance d;
    const auto t0 = std::chrono::steady_clock::now();
    mesh_distance(A, Eigen::Isometry3d::Identity(), B, poses[k++ % poses.size()], ws, d);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    culled.push_back(std::min(d.stats.culled_percent_a, d.stats.culled_percent_b));
    node_pairs += double(d.stats.node_pairs), leaf_pairs += double(d.stats.leaf_pairs),
        triangle_pairs += double(d.stats.triangle_pairs);
  }
  report(state, scene, us, culled);
  state.counters["min_culled_pct"] = *std::min_element(culled.begin(), culled.end());
  state.counters["median_culled_pct"] = median(culled);
  state.counters["node_pairs"] = node_pairs / double(us.size());
  state.counters["leaf_pairs"] = leaf_pairs / double(us.size());
  state.counters["triangle_pairs"] = triangle_pairs / double(us.size());
}

void Minksum(benchmark::State& state, Scene scene) {
  const tools::Mesh &ma = mesh(scene.a), &mb = mesh(scene.b);
  Octree A, B;
  build_octree(ma.vertices, ma.triangles, A);
  build_octree(mb.vertices, mb.triangles, B);
  run_minksum(state, A, B, scene);
  state.counters["bytes_per_triangle"] = double(A.bytes()) / double(ma.triangles.size());
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
  report(state, scene, us, {});
  state.counters["bytes_per_triangle"] = double(fcl.bytes_a()) / double(ma.triangles.size());
}

void Build(benchmark::State& state, std::string name) {
  const tools::Mesh& m = mesh(name);
  for (auto _ : state) {
    Octree A;
    build_octree(m.vertices, m.triangles, A);
    state.counters["bytes"] = double(A.bytes());
  }
}

// A cloud of `count` points sampled from a mesh's surface (seeded), cached.
const std::vector<Eigen::Vector3d>& cloud(const std::string& name, int count) {
  static std::map<std::pair<std::string, int>, std::vector<Eigen::Vector3d>> cache;
  auto& c = cache[{name, count}];
  if (c.empty()) c = tools::sample_surface(mesh(name), count, 2026);
  return c;
}

struct CloudScene {
  std::string a, b;    // the meshes sampled
  int na = 0, nb = 0;  // points per cloud
};

void PointMinksum(benchmark::State& state, CloudScene scene) {
  Octree A, B;
  build_octree(cloud(scene.a, scene.na), A);
  build_octree(cloud(scene.b, scene.nb), B);
  run_minksum(state, A, B, Scene{scene.a, scene.b, true});
}

void PointNanoflann(benchmark::State& state, CloudScene scene) {
  const auto &ca = cloud(scene.a, scene.na), &cb = cloud(scene.b, scene.nb);
  peers::NanoflannCloudPair pair(ca, cb);
  const auto poses = poses_of(Scene{scene.a, scene.b, true});
  std::vector<double> us;
  size_t k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(pair.distance(poses[k++ % poses.size()]));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  report(state, Scene{scene.a, scene.b, true}, us, {});
}

void PointBuildMinksum(benchmark::State& state, std::pair<std::string, int> what) {
  const auto& c = cloud(what.first, what.second);
  for (auto _ : state) {
    Octree A;
    build_octree(c, A);
    state.counters["bytes_per_point"] = double(A.bytes()) / double(c.size());
  }
}

void PointBuildNanoflann(benchmark::State& state, std::pair<std::string, int> what) {
  const auto& c = cloud(what.first, what.second);
  const std::vector<Eigen::Vector3d> none;
  for (auto _ : state) {
    peers::NanoflannCloudPair pair(c, none);  // the tree goes on the larger cloud: this one
    state.counters["bytes_per_point"] = double(pair.bytes()) / double(c.size());
  }
}

// Shape-mesh rows: a sphere (5 mm) or a capsule (10 mm half length, 4 mm radius) against the
// full bunny, banded poses by the tool's 20 mm size; FCL's sphere and capsule against its BVH.
void tool_shapes(const std::string& tool, ConvexShape& shape, peers::PeerShape& peer) {
  if (tool == "sphere") {
    shape_from_sphere(0.005, shape);
    peer.kind = peers::PeerShape::Kind::Sphere, peer.radius = 0.005;
  } else {
    shape_from_capsule(0.01, 0.004, shape);
    peer.kind = peers::PeerShape::Kind::Capsule, peer.radius = 0.004, peer.half_length = 0.01;
  }
}

const Octree& bunny_tree() {
  static Octree tree;
  if (tree.nodes.empty()) build_octree(mesh("bun_zipper.ply").vertices, mesh("bun_zipper.ply").triangles, tree);
  return tree;
}

const std::vector<Eigen::Isometry3d>& tool_poses(const std::string& tool) {
  static std::map<std::string, std::vector<Eigen::Isometry3d>> cache;
  std::vector<Eigen::Isometry3d>& poses = cache[tool];
  if (poses.empty()) {
    ConvexShape shape;
    peers::PeerShape peer;
    tool_shapes(tool, shape, peer);
    poses = tools::banded_poses(bunny_tree(), shape, 0.02, 2026, kBandedPoses);
  }
  return poses;
}

void ShapeMinksum(benchmark::State& state, std::string tool) {
  ConvexShape shape;
  peers::PeerShape peer;
  tool_shapes(tool, shape, peer);
  const Octree& A = bunny_tree();
  const auto& poses = tool_poses(tool);
  std::vector<double> us;
  double leaves = 0, triangles = 0;
  size_t k = 0;
  for (auto _ : state) {
    MeshDistance d;
    const auto t0 = std::chrono::steady_clock::now();
    mesh_distance(A, Eigen::Isometry3d::Identity(), shape, poses[k++ % poses.size()], d);
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
    leaves += double(d.stats.leaf_pairs), triangles += double(d.stats.triangle_pairs);
  }
  report(state, Scene{"bun_zipper.ply", tool, true}, us, {});
  state.counters["leaves"] = leaves / double(us.size());
  state.counters["triangles"] = triangles / double(us.size());
}

void ShapeFcl(benchmark::State& state, std::string tool, peers::FclSolver solver) {
  ConvexShape shape;
  peers::PeerShape peer;
  tool_shapes(tool, shape, peer);
  const tools::Mesh& m = mesh("bun_zipper.ply");
  peers::FclMeshShape fcl(m.vertices, m.triangles, peer);
  const auto& poses = tool_poses(tool);
  std::vector<double> us;
  size_t k = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    benchmark::DoNotOptimize(fcl.distance(solver, poses[k++ % poses.size()]));
    us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  report(state, Scene{"bun_zipper.ply", tool, true}, us, {});
}

const int kRegistered = [] {
  for (auto [label, file] : {std::pair{"bunny_res2", "bun_zipper_res2.ply"}, std::pair{"bunny_full", "bun_zipper.ply"},
                             std::pair{"concentric_spheres", "sphere_outer"}}) {
    const std::string base = std::string("MeshDistance/") + label + "/";
    const Scene scene{file, label == std::string("concentric_spheres") ? "sphere_inner" : file};
    // At least the 100 poses once each.
    benchmark::RegisterBenchmark((base + "minksum").c_str(), Minksum, scene)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(300);
    benchmark::RegisterBenchmark((base + "fcl_obbrss").c_str(), Fcl, scene)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(300);
    benchmark::RegisterBenchmark((std::string("MeshBuild/") + label).c_str(), Build, file)
        ->Unit(benchmark::kMillisecond);
  }
  // Banded poses: the bunny, and libcgal-demo meshes of other shapes paired (every one used).
  for (auto [label, a, b] :
       {std::tuple{"bunny", "bun_zipper.ply", "bun_zipper.ply"}, std::tuple{"camel_bull", "camel.off", "bull.off"},
        std::tuple{"femur_turbine", "femur.off", "turbine.off"},
        std::tuple{"fandisk_blade", "fandisk.off", "blade.off"}, std::tuple{"blade_camel", "blade.off", "camel.off"},
        std::tuple{"turbine_bull", "turbine.off", "bull.off"}, std::tuple{"ribbon", "ribbon", "ribbon"},
        std::tuple{"flattened", "flattened", "flattened"},
        std::tuple{"flattened_tilted", "flattened_tilted", "flattened_tilted"}}) {
    const std::string base = std::string("MeshDistance/") + label + "/";
    const Scene scene{a, b, true};
    benchmark::RegisterBenchmark((base + "minksum").c_str(), Minksum, scene)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(3 * kBandedPoses);
    benchmark::RegisterBenchmark((base + "fcl_obbrss").c_str(), Fcl, scene)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(3 * kBandedPoses);
  }
  for (const char* tool : {"sphere", "capsule"}) {
    const std::string base = std::string("MeshShapeDistance/") + tool + "_bunny_full/";
    benchmark::RegisterBenchmark((base + "minksum").c_str(), ShapeMinksum, tool)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(3 * kBandedPoses);
    for (auto [name, solver] : {std::pair{"fcl_obbrss_gjk", peers::FclSolver::Gjk},
                                std::pair{"fcl_obbrss_libccd", peers::FclSolver::Libccd}})
      benchmark::RegisterBenchmark((base + name).c_str(), ShapeFcl, tool, solver)
          ->Unit(benchmark::kMicrosecond)
          ->Iterations(3 * kBandedPoses);
  }
  for (const CloudScene& c :
       {CloudScene{"camel.off", "bull.off", 100000, 100000}, CloudScene{"femur.off", "turbine.off", 50000, 200000},
        CloudScene{"fandisk.off", "blade.off", 150000, 150000}}) {
    const std::string base =
        "PointDistance/" + c.a.substr(0, c.a.size() - 4) + "_" + c.b.substr(0, c.b.size() - 4) + "/";
    benchmark::RegisterBenchmark((base + "minksum").c_str(), PointMinksum, c)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(kBandedPoses);
    benchmark::RegisterBenchmark((base + "nanoflann").c_str(), PointNanoflann, c)
        ->Unit(benchmark::kMicrosecond)
        ->Iterations(kBandedPoses);
    for (const auto& [name, n] : {std::pair{c.a, c.na}, std::pair{c.b, c.nb}}) {
      const std::string label = "PointBuild/" + name.substr(0, name.size() - 4) + "_" + std::to_string(n / 1000) + "k/";
      benchmark::RegisterBenchmark((label + "minksum").c_str(), PointBuildMinksum, std::pair{name, n})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
      benchmark::RegisterBenchmark((label + "nanoflann").c_str(), PointBuildNanoflann, std::pair{name, n})
          ->Unit(benchmark::kMillisecond)
          ->Iterations(3);
    }
  }
  return 0;
}();

}  // namespace
