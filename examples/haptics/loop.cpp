// The haptic loop: a scripted tool path over a static mesh (approach, touch, press in, slide,
// leave), one query set per tick, latency percentiles over the run.
#include "haptics/loop.hpp"

#include <minksum/minksum.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <thread>

#include <sched.h>
#include <sys/mman.h>

#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum::haptics {

namespace {

using Eigen::Vector3d;

// Penalty force: a spring along the push-out direction and a damper on the approach speed.
constexpr double kStiffness = 2000;  // N/m
constexpr double kDamping = 5;       // N s/m

// The tool: a surface mesh for the distance, and its hull, prepared once and posed per tick,
// for the penetration depth.
struct Tool {
  tools::Mesh mesh;
  ConvexShape hull;
  bool convex = true;  // the mesh is its hull's surface
};

bool make_tool(const std::string& what, Tool& tool, std::string& name, std::string& error) {
  std::vector<Vector3d> points;
  if (what == "box" || what == "icosa") {
    const double s = what == "box" ? 1.0 : 0.008 / std::sqrt(1 + 1.618034 * 1.618034);
    points = what == "box" ? tools::cube_points() : tools::icosahedron_points();
    for (auto& p : points) p = what == "box" ? Vector3d(0.010 * p.x(), 0.008 * p.y(), 0.006 * p.z()) : Vector3d(s * p);
    name = what == "box" ? "box 20 x 16 x 12 mm" : "icosahedron, 8 mm circumradius";
  } else {
    if (!tools::read_mesh(what, tool.mesh, error)) return false;
    // Scaled to 30 mm across and centred, so that it is a tool, not a second scene.
    Vector3d lo = tool.mesh.vertices[tool.mesh.triangles[0][0]], hi = lo;
    for (const auto& t : tool.mesh.triangles)
      for (int k : t) lo = lo.cwiseMin(tool.mesh.vertices[k]), hi = hi.cwiseMax(tool.mesh.vertices[k]);
    const double scale = 0.03 / (hi - lo).maxCoeff();
    for (auto& v : tool.mesh.vertices) v = scale * (v - (lo + hi) / 2);
    points = tool.mesh.vertices;
    name = what + " (scaled to 30 mm)";
    tool.convex = false;
  }
  if (const Status s = shape_from_points(points, tool.hull); s != Status::Ok)
    return error = "tool: " + std::string(to_string(s)), false;
  if (tool.mesh.triangles.empty()) {  // a convex tool's surface: its hull's faces, fanned
    tool.mesh.vertices = tool.hull.polytope().vertices;
    for (const auto& f : tool.hull.polytope().faces)
      for (size_t k = 1; k + 1 < f.loop.size(); ++k)
        tool.mesh.triangles.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
  }
  if (int(tool.hull.polytope().vertices.size()) > kMaxToolVertices)
    return error = "tool: its hull has more than " + std::to_string(kMaxToolVertices) + " vertices", false;
  return true;
}

// The scripted path, one 4 s cycle: approach from 30 mm straight above the scene's highest
// vertex, touch, press 2 mm in, slide 8 mm to one side and 8 mm to the other while pressed,
// come back up; smooth in time (cosine ramps), so positions and velocities are continuous.
// Nothing of the scene is higher than where the tool presses, so the tool never runs into a
// wall side-on (a penalty depth cannot be continuous there).
struct Path {
  Vector3d top;     // the scene's highest vertex
  double lift = 0;  // the tool's reach below its centre (touching clearance)
  Vector3d at(double t) const {
    const double u = std::fmod(t, 4.0);
    const auto ramp = [](double x) { return 0.5 - 0.5 * std::cos(M_PI * std::clamp(x, 0.0, 1.0)); };
    double clearance = -0.002, slide = 0;
    if (u < 1)
      clearance = 0.03 - 0.032 * ramp(u);  // approach, touch, press
    else if (u < 3)
      slide = 0.008 * std::sin(M_PI * (u - 1));  // slide there and back
    else
      clearance = -0.002 + 0.032 * ramp(u - 3);  // leave
    return top + Vector3d(slide, lift + clearance, 0);
  }
};

// This thread's CPU time (a tick's own compute, whatever the OS does around it).
double thread_cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * double(t.tv_sec) + 1e-3 * double(t.tv_nsec);
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(q * double(v.size())))];
}

// Everything a run sets up before its first tick: all of its allocation happens here.
struct Setup {
  tools::Mesh scene;
  Tool tool;
  Octree scene_tree, tool_tree;
  MeshWorkspace ws;
  Path path;
};

bool set_up(const Options& options, Setup& s, Report& report, std::string& error) {
  if (options.scene.empty() || options.scene == "bunny_full") {
    s.scene = tools::demo_mesh(options.scene.empty() ? "bun_zipper_res2.ply" : "bun_zipper.ply", report.scene_source);
  } else {
    if (!tools::read_mesh(options.scene, s.scene, error)) return false;
    report.scene_source = options.scene;
  }
  if (!make_tool(options.tool, s.tool, report.tool_name, error)) return false;
  // A small tool is fastest as one leaf (a deeper tree multiplies the node pairs).
  OctreeOptions tool_options;
  if (s.tool.mesh.triangles.size() <= 64) tool_options.max_depth = 0;
  if (Status st = build_octree(s.scene.vertices, s.scene.triangles, s.scene_tree); st != Status::Ok)
    return error = "scene: " + std::string(to_string(st)), false;
  if (Status st = build_octree(s.tool.mesh.vertices, s.tool.mesh.triangles, s.tool_tree, tool_options);
      st != Status::Ok)
    return error = "tool: " + std::string(to_string(st)), false;
  make_workspace(s.scene_tree, s.tool_tree, s.ws);
  s.path.top = s.scene.vertices[s.scene.triangles[0][0]];
  for (const auto& t : s.scene.triangles)
    for (int k : t)
      if (s.scene.vertices[k].y() > s.path.top.y()) s.path.top = s.scene.vertices[k];
  for (const auto& v : s.tool.hull.polytope().vertices) s.path.lift = std::max(s.path.lift, -v.y());
  return true;
}

// Paced runs ask for real-time scheduling and locked memory (granted to root or with
// CAP_SYS_NICE / CAP_IPC_LOCK; otherwise the run goes on at normal priority and says so).
void ask_for_realtime(Report& report) {
  sched_param param{};
  param.sched_priority = sched_get_priority_max(SCHED_FIFO) / 2;
  report.realtime_priority = sched_setscheduler(0, SCHED_FIFO, &param) == 0;
  mlockall(MCL_CURRENT | MCL_FUTURE);  // no page fault or swap-in inside the loop
  // One core of its own: no migrations between ticks (the last core; best effort).
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(std::max(0, int(std::thread::hardware_concurrency()) - 1), &one);
  sched_setaffinity(0, sizeof one, &one);
}

// One tick's queries and force, with the tool at `pose` (the scene sits at the identity) moving
// at `velocity`; written to the report at k. A convex tool: contact first (it only looks under
// the tool), the exact distance when there is none. A mesh tool: the mesh-mesh distance, and
// its hull's depth on contact.
void tick(const Options& options, Setup& s, ProximityCache& cache, const Eigen::Isometry3d& pose,
          const Vector3d& velocity, long k, Report& report) {
  const Eigen::Isometry3d scene = Eigen::Isometry3d::Identity();
  const auto distance = [&](MeshDistance& d) {
    return options.coherent ? mesh_distance(s.scene_tree, scene, s.tool_tree, pose, s.ws, cache, d)
                            : mesh_distance(s.scene_tree, scene, s.tool_tree, pose, s.ws, d);
  };
  MeshDistance d;
  MeshContact c;
  double force = 0, along = 0, up = 0;
  bool touching;
  if (s.tool.convex) {
    touching = mesh_contact(s.scene_tree, scene, s.tool.hull, pose, s.ws, c) == Status::Ok && c.intersecting;
    if (!touching) distance(d);
  } else {
    touching = distance(d) == Status::Ok && d.intersecting &&
               mesh_contact(s.scene_tree, scene, s.tool.hull, pose, s.ws, c) == Status::Ok && c.intersecting;
  }
  if (!touching) {
    c = MeshContact{};
  } else {
    const double push =
        kStiffness * c.penetration_depth - kDamping * std::min(0.0, velocity.dot(c.penetration_direction));
    const Vector3d f = std::max(0.0, push) * c.penetration_direction;
    force = f.norm(), along = f.dot(c.penetration_direction), up = f.y();
    ++report.contacts;
  }
  report.distance[k] = d.distance, report.depth[k] = c.penetration_depth;
  report.force[k] = force, report.force_dot_normal[k] = along, report.force_up[k] = up;
}

// The latency percentiles of a finished run.
void summarise(Report& report) {
  report.p50_us = percentile(report.latency_us, 0.5), report.p99_us = percentile(report.latency_us, 0.99);
  report.p999_us = percentile(report.latency_us, 0.999);
  report.max_us = *std::max_element(report.latency_us.begin(), report.latency_us.end());
  report.cpu_p50_us = percentile(report.cpu_us, 0.5), report.cpu_p99_us = percentile(report.cpu_us, 0.99);
  report.cpu_p999_us = percentile(report.cpu_us, 0.999);
  report.cpu_max_us = *std::max_element(report.cpu_us.begin(), report.cpu_us.end());
}

}  // namespace

bool run(const Options& options, long (*allocations)(), Report& report, std::string& error) {
  report = Report{};
  if (!(options.seconds > 0) || !(options.rate > 0) || options.seconds * options.rate > 1e8)
    return error = "--seconds and --rate must be positive (at most 1e8 ticks)", false;
  Setup s;
  if (!set_up(options, s, report, error)) return false;
  const long n = long(std::llround(options.seconds * options.rate));
  for (auto* v : {&report.time, &report.distance, &report.depth, &report.force, &report.latency_us, &report.cpu_us,
                  &report.force_dot_normal, &report.force_up})
    v->assign(size_t(n), 0.0);
  const double dt = 1 / options.rate;
  using clock = std::chrono::steady_clock;
  if (options.realtime) ask_for_realtime(report);
  const auto start = clock::now();
  const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(dt));
  long allocations_after_warmup = 0;
  Vector3d previous = s.path.at(0);
  ProximityCache cache;  // the mesh distance's, from one tick to the next (options.coherent)
  for (long k = 0; k < n; ++k) {
    if (k == options.warmup) allocations_after_warmup = allocations();
    const auto deadline = start + (k + 1) * period;
    if (options.realtime) {
      // Sleep until shortly before the tick, then spin: the kernel's wake-up is late by tens
      // of microseconds, sometimes more, and a haptic tick cannot start late.
      const auto at = start + k * period;
      std::this_thread::sleep_until(at - std::chrono::microseconds(300));
      while (clock::now() < at) {
      }
    }
    const auto t0 = clock::now();
    const double cpu0 = thread_cpu_us();
    try {
      const Eigen::Isometry3d pose(Eigen::Translation3d(s.path.at(double(k) * dt)));
      const Vector3d velocity = (pose.translation() - previous) / dt;
      previous = pose.translation();
      report.time[k] = double(k) * dt;
      tick(options, s, cache, pose, velocity, k, report);
    } catch (...) {
      ++report.exceptions;
    }
    const auto t1 = clock::now();
    report.cpu_us[k] = thread_cpu_us() - cpu0;
    report.latency_us[k] = std::chrono::duration<double, std::micro>(t1 - t0).count();
    report.overruns += report.cpu_us[k] > 1e6 * dt;
    if (options.realtime) {
      const double late = std::chrono::duration<double, std::micro>(t0 - (start + k * period)).count();
      report.misses += t1 > deadline, report.late_starts += late > 50;
      report.max_late_start_us = std::max(report.max_late_start_us, late);
    }
  }
  // -1: this build does not count (allocations() says -1).
  report.allocations = allocations() < 0 ? -1 : n > options.warmup ? allocations() - allocations_after_warmup : 0;
  report.ticks = n;
  summarise(report);
  return true;
}

bool plot(const Report& r, const std::string& png, std::string& error) {
  const std::string data = png + ".dat";
  FILE* f = std::fopen(data.c_str(), "w");
  if (!f) return error = png + ": cannot write " + data, false;
  for (size_t k = 0; k < r.time.size(); ++k)
    std::fprintf(f, "%.6f %.9g %.9g %.9g %.3f\n", r.time[k], 1000 * r.distance[k], 1000 * r.depth[k], r.force[k],
                 r.latency_us[k]);
  std::fclose(f);
  FILE* g = popen("gnuplot 2>&1", "w");
  if (!g) return error = "gnuplot not found (Debian package gnuplot-nox)", false;
  std::fprintf(
      g,
      "set terminal pngcairo size 1200,900 noenhanced\nset output '%s'\nset multiplot layout 2,1 title '%s on %s'\n"
      "set xlabel 'time [s]'\nset ylabel 'distance, depth [mm]'\nset y2label 'force [N]'\nset y2tics\nset ytics "
      "nomirror\n"
      "plot [0:8] '%s' u 1:2 w l t 'distance', '' u 1:3 w l t 'depth', '' u 1:4 axes x1y2 w l t 'force'\n"
      "unset y2label\nunset y2tics\nset xlabel 'tick latency [us]'\nset ylabel 'ticks'\nset logscale y\nbinwidth=1\n"
      "plot '%s' u (binwidth*floor($5/binwidth)):(1.0) smooth freq w boxes t 'latency'\nunset multiplot\n",
      png.c_str(), r.tool_name.c_str(), r.scene_source.c_str(), data.c_str(), data.c_str());
  const int status = pclose(g);
  std::remove(data.c_str());
  if (status != 0) return error = "gnuplot failed (is gnuplot-nox installed?)", false;
  return true;
}

}  // namespace minksum::haptics
