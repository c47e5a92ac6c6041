// minksum distance: exact mesh-mesh distance through octrees (the paper's Section 5.1).
#include <minksum/minksum.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "commands.hpp"
#include "support/mesh_io.hpp"

namespace minksum::cli {

namespace {

double now_us() {
  using namespace std::chrono;
  return duration<double, std::micro>(steady_clock::now().time_since_epoch()).count();
}

std::string json(const MeshDistance& d, double time_us) {
  char buf[1024];
  std::snprintf(buf, sizeof buf,
                "{\"distance\": %.17g, \"closest_points\": [[%.17g, %.17g, %.17g], [%.17g, %.17g, "
                "%.17g]], \"triangles\": [%d, %d], \"candidates\": [%d, %d], \"culled_percent\": "
                "[%.3f, %.3f], \"node_pairs\": %ld, \"time_us\": %.1f}",
                d.distance, d.point_a.x(), d.point_a.y(), d.point_a.z(), d.point_b.x(), d.point_b.y(), d.point_b.z(),
                d.triangle_a, d.triangle_b, d.stats.candidates_a, d.stats.candidates_b, d.stats.culled_percent_a,
                d.stats.culled_percent_b, d.stats.node_pairs, time_us);
  return buf;
}

bool load_mesh(const std::string& path, tools::Mesh& mesh) {
  std::string error;
  if (tools::read_mesh(path, mesh, error, true)) return true;  // faceless PLY, OFF, OBJ, XYZ: a cloud
  std::fprintf(stderr, "minksum: %s\n", error.c_str());
  return false;
}

}  // namespace

int cmd_distance(int argc, char** argv) {
  std::vector<std::string> files;
  std::string pose_text, poses_file;
  bool as_json = false, brute = false, coherent = false;
  for (int k = 0; k < argc; ++k) {
    const std::string a = argv[k];
    if (a == "--json") {
      as_json = true;
    } else if (a == "--brute") {
      brute = true;
    } else if (a == "--coherent") {
      coherent = true;
    } else if (a == "--pose" || a == "--poses") {
      if (k + 1 >= argc) return usage_error(a + " needs a value");
      (a == "--pose" ? pose_text : poses_file) = argv[++k];
    } else if (a.rfind("--", 0) == 0) {
      return usage_error("unknown option '" + a + "'");
    } else {
      files.push_back(a);
    }
  }
  if (files.size() != 0 && files.size() != 2) return usage_error("distance needs two mesh files, or none for the demo");
  if (!pose_text.empty() && !poses_file.empty()) return usage_error("give --pose or --poses, not both");
  if (coherent && (poses_file.empty() || brute)) return usage_error("--coherent needs --poses (and no --brute)");
  tools::Mesh ma, mb;
  if (files.empty()) {
    std::string source;
    ma = mb = tools::demo_mesh("bun_zipper_res2.ply", source);
    if (!as_json && poses_file.empty()) std::printf("demo: two copies of %s\n", source.c_str());
  } else if (!load_mesh(files[0], ma) || !load_mesh(files[1], mb)) {
    return 2;
  }
  std::vector<Eigen::Isometry3d> poses;
  std::string error;
  if (!poses_file.empty()) {
    std::vector<Eigen::Isometry3d> read;
    if (!read_poses(poses_file, read, error)) return usage_error(error);
    for (const auto& p : read) poses.push_back(p);
  } else if (!pose_text.empty()) {
    Eigen::Isometry3d p;
    if (!parse_pose(pose_text, "--pose", p, error)) return usage_error(error);
    poses.push_back(p);
  } else if (files.empty()) {
    // The demo places its second copy beside the first: shifted along +x by 1.1 x the width.
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto& t : ma.triangles)
      for (int v : t) lo = lo.cwiseMin(ma.vertices[v]), hi = hi.cwiseMax(ma.vertices[v]);
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation().x() = 1.1 * (hi.x() - lo.x());
    if (!as_json) std::printf("demo: the second copy moved by +%.4g along x\n", p.translation().x());
    poses.push_back(p);
  } else {
    poses.push_back(Eigen::Isometry3d::Identity());  // the files as given
  }
  Octree A, B;
  const double t0 = now_us();
  const std::string names[2] = {files.empty() ? "demo mesh" : files[0], files.empty() ? "demo mesh" : files[1]};
  for (int k = 0; k < 2; ++k) {
    const tools::Mesh& mesh = k == 0 ? ma : mb;
    if (const Status s = tools::build_tree(mesh, k == 0 ? A : B); s != Status::Ok) {
      std::fprintf(stderr, "minksum: %s: %s\n", names[k].c_str(), to_string(s));
      return 2;
    }
  }
  const double build_us = (now_us() - t0) / 2;
  const bool human = !as_json && poses_file.empty();  // else one JSON line per pose
  const auto size = [](const tools::Mesh& m) {
    return m.triangles.empty() ? std::to_string(m.vertices.size()) + " points"
                               : std::to_string(m.triangles.size()) + " triangles";
  };
  if (human)
    std::printf("octrees: %s and %s, depth %d and %d, %d and %d leaves, %.1f and %.1f KiB, %.0f us per build\n",
                size(ma).c_str(), size(mb).c_str(), A.depth, B.depth, A.leaves, B.leaves, A.bytes() / 1024.0,
                B.bytes() / 1024.0, build_us);
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  ProximityCache cache;  // --coherent: consecutive poses share it
  for (const Eigen::Isometry3d& pose : poses) {
    MeshDistance d;
    const double start = now_us();
    const Status s = brute      ? (d = tools::brute_distance(ma, mb, pose), Status::Ok)
                     : coherent ? mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, cache, d)
                                : mesh_distance(A, Eigen::Isometry3d::Identity(), B, pose, ws, d);
    const double time = now_us() - start;
    if (s != Status::Ok) {
      std::fprintf(stderr, "minksum: pose: %s\n", to_string(s));
      return 2;
    }
    if (!human) {
      std::printf("%s\n", json(d, time).c_str());
    } else {
      std::printf("%s distance %.17g between %s %d and %s %d (%s)\n", brute ? "all-pairs" : "octree", d.distance,
                  ma.triangles.empty() ? "point" : "triangle", d.triangle_a,
                  mb.triangles.empty() ? "point" : "triangle", d.triangle_b,
                  d.intersecting ? "intersecting" : "separated");
      std::printf(
          "candidates %d and %d triangles (%.2f%% and %.2f%% culled), %ld node pairs, "
          "%ld triangle pairs, %.1f us\n",
          d.stats.candidates_a, d.stats.candidates_b, d.stats.culled_percent_a, d.stats.culled_percent_b,
          d.stats.node_pairs, d.stats.triangle_pairs, time);
    }
  }
  return 0;
}

}  // namespace minksum::cli
