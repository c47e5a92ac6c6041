// The haptic loop: a scripted 6-DOF device path over a static mesh (approach, touch, press in,
// slide while turning, leave), one proxy move and contact patch per tick, latency percentiles
// over the run.
#include "haptics/loop.hpp"

#include <minksum/io.hpp>
#include <minksum/minksum.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <sstream>
#include <thread>

#include <sched.h>
#include <sys/mman.h>

#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum::haptics {

namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// The proxy rests this far above a surface it met, so that the next sweep starts apart (a time
// of impact from touching is 0, whatever the motion); the sweeps stop within a quarter of it.
constexpr double kSkin = 4 * kProxyTolerance;  // m
constexpr int kPasses = 3;      // sweeps a tick: the motion, then sliding along one or two surfaces
// Resting on a surface, the proxy follows the device into it by at most this much a tick: far
// enough to stay on a surface that curves away as it slides, and the sweep stays short (its
// cost grows with the triangles within its reach).
constexpr double kFall = 4 * kSkin;  // m

// The tool. A polytope (a box, an icosahedron, a mesh's convex hull) is its hull (the swept
// shape), that hull grown by twice the skin (its contact patch at the proxy, which rests a skin
// away), and the hull's surface (its distance to the scene, which certifies a free move without
// a sweep). A rounded tool (a sphere, a capsule) is its shape alone: its distance to the scene
// gives the clearance, the contact normal and the point the force acts at.
struct Tool {
  tools::Mesh surface;
  ConvexShape hull, skin;
  bool rounded = false;
  double radius = 0;  // how far from its origin a point of it reaches: how far a turn moves it
};

// "sphere:R" or "capsule:H:R" in millimetres (half length H along the tool's z) into a tool.
bool make_rounded_tool(const std::string& what, Tool& tool, std::string& name, std::string& error) {
  const bool sphere = what.rfind("sphere:", 0) == 0;
  const std::string form = sphere ? "sphere:R" : "capsule:H:R";
  std::string numbers = what.substr(what.find(':') + 1);
  for (char& c : numbers) c = c == ':' ? ' ' : c;
  std::istringstream in(numbers);
  double v[2] = {0, 0};
  std::string rest;
  for (int k = 0; k < (sphere ? 1 : 2); ++k)
    if (!(in >> v[k])) return error = "--tool " + what + ": expected " + form + " in mm", false;
  if (in >> rest) return error = "--tool " + what + ": expected " + form + " in mm", false;
  const double r = (sphere ? v[0] : v[1]) / 1000, h = sphere ? 0.0 : v[0] / 1000;
  if (!(r >= 1e-4 && r <= 0.05 && h >= 0 && h <= 0.05))
    return error = "--tool " + what + ": the radius must lie in [0.1, 50] mm and the half length in [0, 50] mm", false;
  const Status st = sphere ? shape_from_sphere(r, tool.hull) : shape_from_capsule(h, r, tool.hull);
  if (st != Status::Ok) return error = "tool: " + std::string(to_string(st)), false;
  tool.rounded = true, tool.radius = h + r;
  char text[96];
  if (sphere)
    std::snprintf(text, sizeof text, "sphere, %.3g mm radius", 1000 * r);
  else
    std::snprintf(text, sizeof text, "capsule, %.3g mm half length, %.3g mm radius", 1000 * h, 1000 * r);
  name = text;
  return true;
}

bool make_tool(const std::string& what, Tool& tool, std::string& name, std::string& error) {
  if (what.rfind("sphere:", 0) == 0 || what.rfind("capsule:", 0) == 0) return make_rounded_tool(what, tool, name, error);
  std::vector<Vector3d> points;
  if (what == "box" || what == "icosa") {
    const double s = what == "box" ? 1.0 : 0.008 / std::sqrt(1 + 1.618034 * 1.618034);
    points = what == "box" ? tools::cube_points() : tools::icosahedron_points();
    for (auto& p : points) p = what == "box" ? Vector3d(0.010 * p.x(), 0.008 * p.y(), 0.006 * p.z()) : Vector3d(s * p);
    name = what == "box" ? "box 20 x 16 x 12 mm" : "icosahedron, 8 mm circumradius";
  } else {
    // The hull of the file's vertices (faces or none), scaled to 30 mm across and centred, so
    // that it is a tool, not a second scene.
    std::vector<Vector3d> read;
    if (!read_points(what, read, error)) return false;
    Vector3d lo = read.front(), hi = lo;
    for (const Vector3d& v : read) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    const double scale = 0.03 / (hi - lo).maxCoeff();
    for (const Vector3d& v : read) points.push_back(scale * (v - (lo + hi) / 2));
    name = what + " (its hull, scaled to 30 mm)";
  }
  if (const Status s = shape_from_points(points, tool.hull); s != Status::Ok)
    return error = "tool: " + std::string(to_string(s)), false;
  const ConvexPolytope& hull = tool.hull.polytope();
  if (int(hull.vertices.size()) > kMaxToolVertices)
    return error = "tool: its hull has more than " + std::to_string(kMaxToolVertices) + " vertices", false;
  // The skin: the hull scaled about its centroid so that every face moves out by at least
  // twice the skin (a face at distance h from the centroid moves out by h times the growth).
  Vector3d centroid = Vector3d::Zero();
  for (const auto& v : hull.vertices) centroid += v / double(hull.vertices.size());
  double inner = std::numeric_limits<double>::infinity();
  for (const auto& f : hull.faces) inner = std::min(inner, f.offset - f.normal.dot(centroid));
  std::vector<Vector3d> grown;
  for (const auto& v : hull.vertices) {
    grown.push_back(centroid + (1 + 2 * kSkin / inner) * (v - centroid));
    tool.radius = std::max(tool.radius, v.norm());
  }
  if (const Status s = shape_from_points(grown, tool.skin); s != Status::Ok)
    return error = "tool: " + std::string(to_string(s)), false;
  tool.surface.vertices = hull.vertices;  // the hull's faces, fanned
  for (const auto& f : hull.faces)
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) tool.surface.triangles.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
  return true;
}

// The scripted device path, one 4 s cycle: approach from 30 mm straight above the scene's top,
// touch, press `press` in, slide 8 mm to one side and back while turning (up to 0.4 rad about
// the vertical and 0.08 rad of roll), come back up. Smooth in time (cosine ramps) unless
// `speed` asks for a straight plunge at that speed. Nothing of the scene is higher than where
// the tool presses, so the tool does not run into a wall side-on.
struct Path {
  Vector3d top;     // the scene's highest vertex (of those, the nearest to the middle)
  double lift = 0;  // the tool's reach below its origin (touching clearance)
  double press = 0.002, speed = 0, reach = 0.008;  // (reach: the slide's, each way)
  Isometry3d at(double t) const {
    const double u = std::fmod(t, 4.0);
    const auto ramp = [](double x) { return 0.5 - 0.5 * std::cos(M_PI * std::clamp(x, 0.0, 1.0)); };
    double clearance = -press, slide = 0, turn = 0;
    if (u < 1)  // approach, touch, press
      clearance = speed > 0 ? std::max(-press, 0.03 - speed * u) : 0.03 - (0.03 + press) * ramp(u);
    else if (u < 3)  // slide there and back, turning
      slide = reach * std::sin(M_PI * (u - 1)), turn = std::sin(M_PI * (u - 1));
    else  // leave
      clearance = -press + (0.03 + press) * ramp(u - 3);
    Isometry3d pose(Eigen::Translation3d(top + Vector3d(slide, lift + clearance, 0)));
    pose.linear() = (Eigen::AngleAxisd(0.4 * turn, Vector3d::UnitY()) * Eigen::AngleAxisd(0.08 * turn, Vector3d::UnitZ()))
                        .toRotationMatrix();
    return pose;
  }
};

// This thread's CPU time (a tick's own compute, whatever the OS does around it).
double thread_cpu_us() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return 1e6 * double(t.tv_sec) + 1e-3 * double(t.tv_nsec);
}

// Everything a run sets up before its first tick (all of its allocation happens here), and the
// state carried from tick to tick.
struct Setup {
  tools::Mesh scene;
  Tool tool;
  Octree scene_tree, tool_tree;
  MeshWorkspace ws;
  Path path;
  ProximityCache cache;  // the distance's, from one tick to the next (options.coherent)
  Isometry3d proxy = Isometry3d::Identity();
  // A certified lower bound of the proxy's distance to the scene: the exact distance apart;
  // after a sweep, the skin it backed off by (or the sweep's tolerance if it met nothing);
  // less the reach of every move made without a sweep since.
  double clearance = 0;
  Vector3d normal = Vector3d::Zero();  // the contact patch's normal at the proxy (0: apart)
  Vector3d force = Vector3d::Zero(), torque = Vector3d::Zero();
  bool touching = false;
};

bool set_up(const Options& options, Setup& s, Report& report, std::string& error) {
  if (options.scene.empty() || options.scene == "bunny_full") {
    report.scene_mesh = options.scene.empty() ? "bun_zipper_res2.ply" : "bun_zipper.ply";
    s.scene = tools::demo_mesh(report.scene_mesh, report.scene_source);
  } else if (options.scene == "bumpy_full") {  // (the instruction budgets' scene: the same on every host)
    s.scene = tools::bumpy_sphere(132);
    report.scene_source = "a generated bumpy sphere of 69,696 triangles";
  } else if (options.scene == "sheet") {
    s.scene = tools::box_mesh(Vector3d(-0.03, -0.0005, -0.03), Vector3d(0.03, 0, 0.03), 12);
    report.scene_source = "a sheet 60 x 60 x 0.5 mm";
  } else {
    if (!tools::read_mesh(options.scene, s.scene, error)) return false;
    if (s.scene.triangles.empty()) return error = options.scene + ": no triangles", false;
    report.scene_source = options.scene;
  }
  if (!make_tool(options.tool, s.tool, report.tool_name, error)) return false;
  // A small tool is fastest as one leaf (a deeper tree multiplies the node pairs).
  OctreeOptions tool_options;
  if (s.tool.surface.triangles.size() <= 64) tool_options.max_depth = 0;
  if (Status st = build_octree(s.scene.vertices, s.scene.triangles, s.scene_tree); st != Status::Ok)
    return error = "scene: " + std::string(to_string(st)), false;
  if (!s.tool.rounded) {
    if (Status st = build_octree(s.tool.surface.vertices, s.tool.surface.triangles, s.tool_tree, tool_options);
        st != Status::Ok)
      return error = "tool: " + std::string(to_string(st)), false;
    make_workspace(s.scene_tree, s.tool_tree, s.ws);
  }
  // The top: the highest vertex, and of several as high, the nearest to the middle.
  Vector3d lo = s.scene.vertices[s.scene.triangles[0][0]], hi = lo;
  for (const auto& t : s.scene.triangles)
    for (int k : t) lo = lo.cwiseMin(s.scene.vertices[k]), hi = hi.cwiseMax(s.scene.vertices[k]);
  const auto off_middle = [&](const Vector3d& v) { return std::hypot(v.x() - (lo + hi).x() / 2, v.z() - (lo + hi).z() / 2); };
  s.path.top = lo;
  for (const auto& t : s.scene.triangles)
    for (int k : t) {
      const Vector3d& v = s.scene.vertices[k];
      if (v.y() > s.path.top.y() || (v.y() == s.path.top.y() && off_middle(v) < off_middle(s.path.top))) s.path.top = v;
    }
  for (const auto& v : s.tool.hull.polytope().vertices)
    s.path.lift = std::max(s.path.lift, -v.y() + s.tool.hull.radius());
  s.path.press = options.press, s.path.speed = options.speed, s.path.reach = options.slide;
  s.proxy = s.path.at(0);
  return true;
}

// What is left of a translation that slides along the surfaces met (their normals, pointing
// out of the scene): no part into any of them. Against one, its tangential part; against two,
// its part along their crease; against more, nothing.
Vector3d slide(Vector3d rest, const Vector3d* normals, int met) {
  for (int i = 0; i < met; ++i)
    if (rest.dot(normals[i]) < 0) rest -= rest.dot(normals[i]) * normals[i];
  bool into = false;
  for (int i = 0; i < met; ++i) into = into || rest.dot(normals[i]) < -1e-12 * rest.norm();
  if (!into) return rest;
  if (met != 2) return Vector3d::Zero();
  const Vector3d crease = normals[0].cross(normals[1]).normalized();
  return crease.allFinite() ? Vector3d(rest.dot(crease) * crease) : Vector3d::Zero();
}

// The proxy swept towards `goal` (time_of_impact against the scene's octree, turning included):
// at an impact it stops a skin back along the contact normal, and with `sliding` the rest of
// its translation slides along the surfaces met, its turn waiting for the next tick. Returns
// the sweeps made.
int sweep_proxy(Setup& s, Isometry3d goal, bool sliding) {
  Isometry3d& proxy = s.proxy;
  Vector3d normals[kPasses];
  int met = 0;
  for (int pass = 0; pass < kPasses; ++pass) {
    TimeOfImpact toi;
    const Status st = time_of_impact(s.scene_tree, Isometry3d::Identity(), s.tool.hull, proxy, goal, toi, kProxyTolerance);
    if (st != Status::Ok) return pass + 1;  // (poses and shapes are checked at set-up)
    if (!toi.hit) {  // (no contact within the tolerance up to the goal)
      proxy = goal, s.clearance = kProxyTolerance / 2;  // (a miss: never within half the tolerance)
      return pass + 1;
    }
    // At time 0 the proxy touches already (a back-off that met another surface): it backs off
    // along the contact normal, as far as the shapes overlap, and tries again.
    // Else, after the impact, the supporting planes along the normal lie between 0 and the
    // tolerance apart: a skin along it, they are a skin apart (and so are the shapes).
    proxy = Motion{proxy, goal}.at(toi.time);  // (the motion the sweep took)
    proxy.translation() += (kSkin + (toi.time == 0 ? (toi.point_a - toi.point_b).norm() : 0.0)) * toi.normal;
    s.clearance = toi.time > 0 ? kSkin : 0.0;
    normals[met++] = toi.normal;
    const Vector3d rest = slide(goal.translation() - proxy.translation(), normals, met);
    if (!sliding || rest.norm() < 1e-2 * kSkin) return pass + 1;  // (nothing left worth a sweep)
    goal.linear() = proxy.linear(), goal.translation() = proxy.translation() + rest;
  }
  return kPasses;
}

// Moves the proxy towards the device pose without ever entering the scene: Zilles and
// Salisbury's god object (1995) in six degrees of freedom. Resting on a surface (s.normal),
// it first moves along the surface and turns, then follows the device into it by at most
// kFall (so that a turn or a slide is not cut short by the press). A move needs no sweep where
// no point of the tool moves farther than the clearance (Mirtich's bound: |dx| + angle *
// radius): resting, the slide and the turn of a tick usually fit in the skin. Returns the
// sweeps made.
int move_proxy(Setup& s, const Isometry3d& device) {
  const double into = std::max(0.0, -(device.translation() - s.proxy.translation()).dot(s.normal));
  Isometry3d along = device;
  along.translation() += into * s.normal;
  const double turn = Eigen::AngleAxisd(Eigen::Matrix3d(s.proxy.linear().transpose() * along.linear())).angle();
  const double reach = (along.translation() - s.proxy.translation()).norm() + turn * s.tool.radius;
  int sweeps = 0;
  if (reach < s.clearance) {
    s.proxy = along, s.clearance -= reach;
  } else {
    sweeps += sweep_proxy(s, along, true);
  }
  if (into > 0) {
    Isometry3d down = s.proxy;
    down.translation() -= std::min(into, kFall) * s.normal;
    sweeps += sweep_proxy(s, down, false);
  }
  return sweeps;
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

// What the tool touches at the proxy: whether it is within twice the skin of the scene, the
// push-out normal and the point the force acts at; apart, its distance (0 if unknown).
struct Touch {
  bool touching = false;
  Vector3d normal = Vector3d::Zero(), centre = Vector3d::Zero();
  double distance = 0;
};

// A polytope tool: the skin's contact patch (its area-weighted normal and centre turn
// continuously as the tool slides over facets); apart, the hull's distance to the scene.
// A rounded tool: its distance to the scene; within twice the skin, the normal from the
// scene's nearest point to the tool's (the gradient of the distance: continuous as a sphere
// slides) and that point. (Coherent: each distance starts from the last tick's answer.)
Touch touch(const Options& options, Setup& s) {
  const Isometry3d scene = Isometry3d::Identity();
  Touch t;
  MeshDistance d;
  if (s.tool.rounded) {
    const Status st = options.coherent ? mesh_distance(s.scene_tree, scene, s.tool.hull, s.proxy, s.cache, d)
                                       : mesh_distance(s.scene_tree, scene, s.tool.hull, s.proxy, d);
    if (st != Status::Ok) return t;
    t.touching = d.distance < 2 * kSkin;
    if (!t.touching) return t.distance = d.distance, t;
    // (The proxy rests a skin away; met inside, the triangle's own normal.)
    const Vector3d gap = d.point_b - d.point_a;
    const auto& tri = s.scene_tree.triangles[size_t(d.triangle_a)];
    const Vector3d* v = s.scene_tree.vertices.data();
    t.normal = gap.norm() > 0 ? Vector3d(gap.normalized())
                              : Vector3d((v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]).normalized());
    t.centre = d.point_a;
    return t;
  }
  MeshContact c;
  t.touching = mesh_contact(s.scene_tree, scene, s.tool.skin, s.proxy, s.ws, c) == Status::Ok && c.intersecting;
  if (t.touching) return t.normal = c.penetration_direction, t.centre = c.centre, t;
  const Status st = options.coherent ? mesh_distance(s.scene_tree, scene, s.tool_tree, s.proxy, s.ws, s.cache, d)
                                     : mesh_distance(s.scene_tree, scene, s.tool_tree, s.proxy, s.ws, d);
  if (st == Status::Ok && !d.intersecting) t.distance = d.distance;
  return t;
}

// One tick with the device at `device` moving at `velocity` (the scene sits at the identity),
// written to the report at k (-1: not traced): the proxy moves, the contact at the proxy gives the normal and
// the centre the force acts at, and the spring from the device to the proxy along that normal
// its size. Apart, the proxy's distance (coherent: started from the last tick's).
void tick(const Options& options, Setup& s, const Isometry3d& device, const Vector3d& velocity, long k,
          Report& report) {
  report.sweeps += move_proxy(s, device);
  const Touch c = touch(options, s);
  const bool touching = c.touching;
  const double distance = c.distance;
  if (!touching) s.clearance = std::max(s.clearance, distance);
  Vector3d force = Vector3d::Zero(), torque = Vector3d::Zero();
  double depth = 0;
  if (touching) {
    const Vector3d& u = c.normal;
    depth = std::max(0.0, (s.proxy.translation() - device.translation()).dot(u));
    const double push = options.stiffness * depth - options.damping * std::min(0.0, velocity.dot(u));
    if (depth > 0 && push > 0) force = push * u;
    torque = (c.centre - device.translation()).cross(force);
    ++report.contacts;
  }
  if (touching && s.touching) {  // steady contact: how smooth the rendering is
    report.max_force_jump = std::max(report.max_force_jump, (force - s.force).norm());
    report.max_torque_jump = std::max(report.max_torque_jump, (torque - s.torque).norm());
  }
  s.force = force, s.torque = torque, s.touching = touching;
  s.normal = touching ? c.normal : Vector3d::Zero();
  if (k < 0) return;  // (past the traced ticks)
  const size_t i = size_t(k);
  report.distance[i] = distance, report.depth[i] = depth, report.force[i] = force.norm();
  report.torque[i] = torque.norm(), report.force_dot_normal[i] = touching ? force.dot(c.normal) : 0;
  report.force_up[i] = force.y(), report.device_y[i] = device.translation().y();
  report.proxy_y[i] = s.proxy.translation().y(), report.proxy[i] = s.proxy;
}

}  // namespace

bool run(const Options& options, long (*allocations)(), Report& report, std::string& error) {
  report = Report{};
  if (!(options.seconds > 0) || !(options.rate >= 1 && options.rate <= 1e5) || options.seconds * options.rate > 1e8)
    return error = "--seconds must be positive and --rate within [1, 100000] Hz (at most 1e8 ticks)", false;
  if (std::llround(options.seconds * options.rate) < 1)  // (no tick: no latency to report)
    return error = "--seconds " + std::to_string(options.seconds) + " at --rate " + std::to_string(options.rate) +
                   " Hz is less than one tick", false;
  if (!(options.slide >= 0 && options.slide <= 0.1)) return error = "--slide must lie in [0, 100] mm", false;
  Setup s;
  if (!set_up(options, s, report, error)) return false;
  const long n = long(std::llround(options.seconds * options.rate));
  const size_t traced = size_t(std::clamp(options.traced, 0L, n));
  for (auto* v : {&report.time, &report.distance, &report.depth, &report.force, &report.latency_us, &report.cpu_us,
                  &report.force_dot_normal, &report.force_up, &report.torque, &report.device_y, &report.proxy_y})
    v->assign(traced, 0.0);
  report.proxy.assign(traced, Isometry3d::Identity());
  Latencies wall_us, cpu_us;  // (every tick's, in fixed memory)
  const double dt = 1 / options.rate;
  using clock = std::chrono::steady_clock;
  if (options.realtime) ask_for_realtime(report);
  const auto start = clock::now();
  const auto period = std::chrono::duration_cast<clock::duration>(std::chrono::duration<double>(dt));
  long allocations_after_warmup = 0;
  Vector3d previous = s.path.at(0).translation();
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
      const Isometry3d device = s.path.at(double(k) * dt);
      const Vector3d velocity = (device.translation() - previous) / dt;
      previous = device.translation();
      tick(options, s, device, velocity, k < long(traced) ? k : -1, report);
      if (k < long(traced)) report.time[size_t(k)] = double(k) * dt;
    } catch (...) {
      ++report.exceptions;
    }
    const auto t1 = clock::now();
    const double cpu = thread_cpu_us() - cpu0, wall = std::chrono::duration<double, std::micro>(t1 - t0).count();
    cpu_us.add(cpu), wall_us.add(wall);
    if (k < long(traced)) report.cpu_us[size_t(k)] = cpu, report.latency_us[size_t(k)] = wall;
    report.overruns += cpu > 1e6 * dt;
    if (options.realtime) {
      const double late = std::chrono::duration<double, std::micro>(t0 - (start + k * period)).count();
      report.misses += t1 > deadline, report.late_starts += late > 50;
      report.max_late_start_us = std::max(report.max_late_start_us, late);
    } else {
      report.misses += wall > 1e6 * dt;  // (no schedule: a tick longer than the period)
    }
  }
  // -1: this build does not count (allocations() says -1).
  report.allocations = allocations() < 0 ? -1 : n > options.warmup ? allocations() - allocations_after_warmup : 0;
  report.ticks = n;
  report.p50_us = wall_us.percentile(0.5), report.p99_us = wall_us.percentile(0.99);
  report.p999_us = wall_us.percentile(0.999), report.max_us = wall_us.max();
  report.cpu_p50_us = cpu_us.percentile(0.5), report.cpu_p99_us = cpu_us.percentile(0.99);
  report.cpu_p999_us = cpu_us.percentile(0.999), report.cpu_max_us = cpu_us.max();
  return true;
}

void Latencies::add(double us) {
  // In 0.01 us: below 2 kSub one bucket each, then kSub buckets per doubling.
  const auto x = static_cast<unsigned long long>(std::clamp(us * 100, 0.0, 1.6e10));
  int b = int(x);
  if (x >= 2 * kSub) {
    const int e = 63 - __builtin_clzll(x) - 9;  // x >> e in [kSub, 2 kSub)
    b = 2 * kSub + (e - 1) * kSub + int(x >> e) - kSub;
  }
  ++count_[size_t(std::min(b, kBuckets - 1))], ++n_;
  max_ = std::max(max_, us);
}

double Latencies::percentile(double q) const {
  const long rank = std::min(n_ - 1, long(q * double(n_)));
  long seen = 0;
  for (int b = 0; b < kBuckets; ++b) {
    seen += count_[size_t(b)];
    if (seen <= rank) continue;
    if (b < 2 * kSub) return std::min(max_, 0.01 * (b + 1));
    const int e = (b - 2 * kSub) / kSub + 1, m = (b - 2 * kSub) % kSub + kSub;
    return std::min(max_, 0.01 * double((static_cast<unsigned long long>(m) + 1) << e));
  }
  return max_;
}

bool plot(const Report& r, const std::string& png, std::string& error) {
  const std::string data = png + ".dat";
  FILE* f = std::fopen(data.c_str(), "w");
  if (!f) return error = png + ": cannot write " + data, false;
  for (size_t k = 0; k < r.time.size(); ++k)
    std::fprintf(f, "%.6f %.9g %.9g %.9g %.3f %.9g\n", r.time[k], 1000 * r.distance[k], 1000 * r.depth[k], r.force[k],
                 r.latency_us[k], 1000 * r.torque[k]);
  std::fclose(f);
  FILE* g = popen("gnuplot 2>&1", "w");
  if (!g) return error = "gnuplot not found (Debian package gnuplot-nox)", false;
  std::fprintf(
      g,
      "set terminal pngcairo size 1200,1200 noenhanced\nset output '%s'\nset multiplot layout 3,1 title '%s on %s'\n"
      "set xlabel 'time [s]'\nset ylabel 'distance, depth [mm]'\n"
      "plot [0:8] '%s' u 1:2 w l t 'proxy distance', '' u 1:3 w l t 'device depth past the proxy'\n"
      "set ylabel 'force [N]'\nset y2label 'torque [N mm]'\nset y2tics\nset ytics nomirror\n"
      "plot [0:8] '' u 1:4 w l t '|force|', '' u 1:6 axes x1y2 w l t '|torque| about the device origin'\n"
      "unset y2label\nunset y2tics\nset xlabel 'tick latency [us]'\nset ylabel 'ticks'\nset logscale y\nbinwidth=1\n"
      "plot '%s' u (binwidth*floor($5/binwidth)):(1.0) smooth freq w boxes t 'latency'\nunset multiplot\n",
      png.c_str(), r.tool_name.c_str(), r.scene_source.c_str(), data.c_str(), data.c_str());
  const int status = pclose(g);
  std::remove(data.c_str());
  if (status != 0) return error = "gnuplot failed (is gnuplot-nox installed?)", false;
  return true;
}

}  // namespace minksum::haptics
