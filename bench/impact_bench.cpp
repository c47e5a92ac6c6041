// Time of impact: minksum's time_of_impact (exact for a translation, conservative advancement
// on the exact distance when turning) against Bullet (btSubsimplexConvexCast translating,
// btContinuousConvexCollision turning) and FCL's continuousCollide (conservative advancement,
// GJK). B sweeps through A within a tick along 1,024 motions: from a contact pose lifted by
// `lift` along a direction to the pose as far beyond it, turning by 0.5 rad about a varying
// axis or not. The face families slide down onto A's top face (a face meeting a face: every
// step of a conservative advancement lands on a tie), Table 1's pairs cross from every side
// (from 2.2 times the larger radius, so apart at both ends).
//   TimeOfImpact/<pair>/<translation|turning>/<minksum|bullet_ccd|fcl_ccd>
// Counters: hits (the share of motions that hit), iterations (minksum's exact queries per
// motion), and for the peers dt_max, the largest |time - minksum's time| over the motions
// both say hit (minksum's stops within 1e-12 of the size translating and 1e-6 turning;
// Bullet's cast within 1e-15 and its advancement within 1e-3, absolute; FCL's once a step is
// under 1e-4 of the tick).
// A convex tool against a mesh: the haptics box tool (20 x 16 x 12 mm) onto the full bunny,
// 256 motions, each from 30 mm above a triangle's centre along its normal to 10 mm below it
// (across the surface), turning by 0.5 rad or not; FCL's peer is its OBBRSS BVH against an
// fcl::Box (conservative advancement, GJK).
//   TimeOfImpact/bunny_mesh/<translation|turning>/<minksum|fcl_ccd>
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>

#include "support/bullet_peer.hpp"
#include "support/fcl_peer.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

constexpr int kMotions = 1024;

struct Motion {
  Isometry3d b0, b1;
};

enum class Method { Minksum, Bullet, Fcl };
constexpr Method kMethods[] = {Method::Minksum, Method::Bullet, Method::Fcl};
const char* name(Method m) { return m == Method::Minksum ? "minksum" : m == Method::Bullet ? "bullet_ccd" : "fcl_ccd"; }

// Motion k of B about the contact pose `at`: from `at` lifted by `lift` along u to as far
// beyond, turning by 0.5 rad about an axis that varies with k, if `turning`.
Motion sweep(const Isometry3d& at, const Vector3d& u, double lift, int k, bool turning) {
  Motion m{at, at};
  m.b0.translation() += lift * u, m.b1.translation() -= lift * u;
  if (turning) {
    const double s = 2 * M_PI * k / kMotions;
    const Vector3d axis = Vector3d(std::cos(s), std::sin(2 * s), 0.5 + std::sin(s)).normalized();
    m.b0.linear() = at.linear() * Eigen::AngleAxisd(-0.25, axis).toRotationMatrix();
    m.b1.linear() = at.linear() * Eigen::AngleAxisd(0.25, axis).toRotationMatrix();
  }
  return m;
}

// What a run reports: the share of motions that hit, and minksum's GJK iterations per motion or
// a peer's largest |time - minksum's time| over the motions both say hit (the first pass).
struct Tally {
  long hits = 0, ticks = 0;
  double dt_max = 0;
  void add(bool hit, double time, bool reference_hit, double reference, bool first_pass) {
    hits += hit;
    if (hit && reference_hit && first_pass) dt_max = std::max(dt_max, std::abs(time - reference));
  }
  void report(benchmark::State& state, Method method, double iterations) const {
    state.counters["hits"] = double(hits) / double(std::max(1L, ticks));
    if (method == Method::Minksum)
      state.counters["iterations"] = iterations;
    else
      state.counters["dt_max"] = dt_max;
  }
};

struct Pair {
  std::vector<Vector3d> a, b;
  const Box *box_a = nullptr, *box_b = nullptr;
};

void Impact(benchmark::State& state, const Pair& pair, const std::vector<Motion>& motions, bool turning, Method method) {
  ConvexShape A, B;
  if ((pair.box_a ? shape_from_box(*pair.box_a, A) : shape_from_points(pair.a, A)) != Status::Ok ||
      (pair.box_b ? shape_from_box(*pair.box_b, B) : shape_from_points(pair.b, B)) != Status::Ok) {
    state.SkipWithError("shape");
    return;
  }
  const Isometry3d a0 = Isometry3d::Identity();
  // minksum's times, the reference of the peers' dt_max.
  std::vector<double> reference(motions.size());
  std::vector<char> reference_hit(motions.size());
  long iterations = 0;
  for (size_t k = 0; k < motions.size(); ++k) {
    TimeOfImpact toi;
    if (time_of_impact(A, a0, a0, B, motions[k].b0, motions[k].b1, toi) != Status::Ok) {
      state.SkipWithError("time_of_impact");
      return;
    }
    reference[k] = toi.time, reference_hit[k] = toi.hit, iterations += toi.iterations;
  }
  // A peer's box sits at its own origin, unturned (the families' boxes are centred at the origin): placed by the pose times the box's frame.
  const bool boxes = pair.box_a && pair.box_b;
  const auto frame = [boxes](const Box* box) {
    Isometry3d f = Isometry3d::Identity();
    if (boxes) f.linear() = box->rotation, f.translation() = box->center;
    return f;
  };
  const Isometry3d fa = frame(pair.box_a), fb = frame(pair.box_b);
  // The peers hold boxes as boxes, as minksum does.
  std::unique_ptr<peers::BulletPair> bullet;
  std::unique_ptr<peers::FclPair> fcl;
  if (method == Method::Bullet)
    bullet = boxes ? std::make_unique<peers::BulletPair>(pair.box_a->half_extents, pair.box_b->half_extents)
                   : std::make_unique<peers::BulletPair>(A.polytope(), B.polytope());
  if (method == Method::Fcl)
    fcl = boxes ? std::make_unique<peers::FclPair>(*pair.box_a, *pair.box_b)
                : std::make_unique<peers::FclPair>(A.polytope(), B.polytope());
  Tally tally;
  for (auto _ : state) {
    const size_t k = size_t(tally.ticks++ % kMotions);
    const Motion& m = motions[k];
    double time = 1;
    bool hit = false;
    if (method == Method::Minksum) {
      TimeOfImpact toi;
      time_of_impact(A, a0, a0, B, m.b0, m.b1, toi);
      time = toi.time, hit = toi.hit;
    } else if (method == Method::Bullet) {
      Vector3d normal;
      hit = bullet->time_of_impact(a0 * fa, a0 * fa, m.b0 * fb, m.b1 * fb, turning, time, normal);
    } else {
      hit = fcl->time_of_impact(peers::FclSolver::Gjk, a0 * fa, a0 * fa, m.b0 * fb, m.b1 * fb, turning, time);
    }
    benchmark::DoNotOptimize(time);
    tally.add(hit, time, reference_hit[k], reference[k], tally.ticks <= kMotions);
  }
  tally.report(state, method, double(iterations) / double(motions.size()));
}

constexpr int kMeshMotions = 256;

struct MeshScene {
  tools::Mesh mesh;
  Octree tree;
  ConvexShape tool;
  Box box;
  std::vector<Motion> motions[2];  // translation, turning
};

const MeshScene& mesh_scene() {
  static const MeshScene scene = [] {
    MeshScene s;
    std::string source;
    s.mesh = tools::demo_mesh("bun_zipper.ply", source);
    build_octree(s.mesh.vertices, s.mesh.triangles, s.tree);
    s.box.half_extents = Vector3d(0.010, 0.008, 0.006);
    shape_from_box(s.box, s.tool);
    for (int k = 0; k < kMeshMotions; ++k) {
      const auto& t = s.mesh.triangles[size_t(k) * s.mesh.triangles.size() / kMeshMotions];
      const Vector3d p[3] = {s.mesh.vertices[t[0]], s.mesh.vertices[t[1]], s.mesh.vertices[t[2]]};
      const Vector3d n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
      const Isometry3d at(Eigen::Translation3d((p[0] + p[1] + p[2]) / 3 + 0.01 * n));
      for (bool turning : {false, true}) s.motions[turning].push_back(sweep(at, n, 0.02, k, turning));
    }
    return s;
  }();
  return scene;
}

void MeshImpact(benchmark::State& state, bool turning, Method method) {
  const MeshScene& s = mesh_scene();
  const std::vector<Motion>& motions = s.motions[turning];
  const Isometry3d still = Isometry3d::Identity();
  std::vector<double> reference(motions.size());
  std::vector<char> reference_hit(motions.size());
  long iterations = 0;
  for (size_t k = 0; k < motions.size(); ++k) {
    TimeOfImpact toi;
    if (time_of_impact(s.tree, still, s.tool, motions[k].b0, motions[k].b1, toi) != Status::Ok) {
      state.SkipWithError("time_of_impact");
      return;
    }
    reference[k] = toi.time, reference_hit[k] = toi.hit, iterations += toi.iterations;
  }
  std::unique_ptr<peers::FclMeshTool> fcl;
  if (method == Method::Fcl) fcl = std::make_unique<peers::FclMeshTool>(s.mesh.vertices, s.mesh.triangles, s.box.half_extents);
  Tally tally;
  for (auto _ : state) {
    const size_t k = size_t(tally.ticks++ % kMeshMotions);
    double time = 1;
    bool hit;
    if (method == Method::Minksum) {
      TimeOfImpact toi;
      time_of_impact(s.tree, still, s.tool, motions[k].b0, motions[k].b1, toi);
      time = toi.time, hit = toi.hit;
    } else {
      hit = fcl->time_of_impact(motions[k].b0, motions[k].b1, turning, time);
    }
    benchmark::DoNotOptimize(time);
    tally.add(hit, time, reference_hit[k], reference[k], tally.ticks <= kMeshMotions);
  }
  tally.report(state, method, double(iterations) / double(motions.size()));
}

// Tools of every size on the full bunny (diagonal D): an icosahedron of radius 0.5 D (the
// mesh's own size), 0.1 D and 0.02 D; 64 surface points (triangle centres p, normals n), one
// motion each: starting in contact (centre at p, half the tool below the surface; the answer
// is time 0), and starting clear (the tool's surface 0.1 D above p, moving 0.2 D down along
// -n; starts where the tool already meets the non-convex bunny are left out), with the same
// tool's mesh distance at the clear start for scale (the tool's hull as a mesh).
//   TimeOfImpact/bunny_mesh/tool_<0.5|0.1|0.02>/<in_contact|clear|distance_at_clear_start>
struct ToolScene {
  ConvexShape tool;
  Octree tool_tree;
  std::vector<Motion> in_contact, clear;
};

const ToolScene& tool_scene(double fraction) {
  static std::map<double, ToolScene> scenes;
  auto [it, fresh] = scenes.try_emplace(fraction);
  ToolScene& s = it->second;
  if (!fresh) return s;
  const MeshScene& m = mesh_scene();
  Vector3d lo = m.mesh.vertices[0], hi = lo;
  for (const auto& v : m.mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double D = (hi - lo).norm(), R = fraction * D;
  const std::vector<Vector3d> points = tools::scaled(tools::icosahedron_points(), R / tools::icosahedron_points()[0].norm());
  shape_from_points(points, s.tool);
  std::vector<std::array<int, 3>> fan;
  for (const auto& f : s.tool.polytope().faces)
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) fan.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
  build_octree(s.tool.polytope().vertices, fan, s.tool_tree);
  MeshWorkspace ws;
  make_workspace(m.tree, s.tool_tree, ws);
  for (size_t k = 0; s.in_contact.size() < 64 && k < 4096; ++k) {
    const auto& t = m.mesh.triangles[k * 7919 % m.mesh.triangles.size()];
    const Vector3d p[3] = {m.mesh.vertices[t[0]], m.mesh.vertices[t[1]], m.mesh.vertices[t[2]]};
    const Vector3d c = (p[0] + p[1] + p[2]) / 3, n = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    const Isometry3d start(Eigen::Translation3d(c + (R + 0.1 * D) * n));
    MeshDistance d;
    if (mesh_distance(m.tree, Isometry3d::Identity(), s.tool_tree, start, ws, d) != Status::Ok || d.intersecting)
      continue;
    s.in_contact.push_back({Isometry3d(Eigen::Translation3d(c)), Isometry3d(Eigen::Translation3d(c - 0.2 * D * n))});
    s.clear.push_back({start, Isometry3d(Eigen::Translation3d(c + (R - 0.1 * D) * n))});
  }
  return s;
}

enum class ToolRow { InContact, Clear, Distance };

void ToolSweep(benchmark::State& state, double fraction, ToolRow row) {
  const MeshScene& m = mesh_scene();
  const ToolScene& s = tool_scene(fraction);
  const std::vector<Motion>& motions = row == ToolRow::InContact ? s.in_contact : s.clear;
  if (motions.empty()) return state.SkipWithError("no clear start");
  const Isometry3d still = Isometry3d::Identity();
  MeshWorkspace ws;
  make_workspace(m.tree, s.tool_tree, ws);
  long ticks = 0, hits = 0, iterations = 0;
  for (auto _ : state) {
    const Motion& x = motions[size_t(ticks++) % motions.size()];
    if (row == ToolRow::Distance) {
      MeshDistance d;
      mesh_distance(m.tree, still, s.tool_tree, x.b0, ws, d);
      benchmark::DoNotOptimize(d.distance);
    } else {
      TimeOfImpact toi;
      time_of_impact(m.tree, still, s.tool, x.b0, x.b1, toi);
      hits += toi.hit, iterations += toi.iterations;
      benchmark::DoNotOptimize(toi.time);
    }
  }
  state.counters["motions"] = double(motions.size());
  if (row != ToolRow::Distance) {
    state.counters["hits"] = double(hits) / double(std::max(1L, ticks));
    state.counters["iterations"] = double(iterations) / double(std::max(1L, ticks));
  }
}

const int registered = [] {
  for (double fraction : {0.5, 0.1, 0.02})
    for (const auto& [row, label] : {std::pair{ToolRow::InContact, "in_contact"}, {ToolRow::Clear, "clear"},
                                     {ToolRow::Distance, "distance_at_clear_start"}}) {
      char base[96];
      std::snprintf(base, sizeof base, "TimeOfImpact/bunny_mesh/tool_%g/%s", fraction, label);
      benchmark::RegisterBenchmark(base, ToolSweep, fraction, row);
    }
  for (bool turning : {false, true})
    for (Method method : {Method::Minksum, Method::Fcl})
      benchmark::RegisterBenchmark(
          (std::string("TimeOfImpact/bunny_mesh/") + (turning ? "turning/" : "translation/") + name(method)).c_str(),
          MeshImpact, turning, method);
  static std::vector<Pair> pairs;
  static std::vector<std::vector<Motion>> motions;
  static std::vector<std::string> names;
  static const std::vector<tools::FacePair> faces = tools::face_pairs();
  static const std::vector<tools::Table1Pair> table1 = tools::table1_pairs();
  pairs.reserve(faces.size() + table1.size());
  motions.reserve(2 * (faces.size() + table1.size()));
  // The face families: down onto A's top face from 0.5 above, sliding sideways by up to 0.2.
  for (const auto& f : faces) {
    pairs.push_back({f.a, f.b, f.a_is_box ? &f.box_a : nullptr, f.b_is_box ? &f.box_b : nullptr});
    names.push_back(f.name);
  }
  for (const auto& t : table1) {
    pairs.push_back({t.a, t.b});
    names.push_back(t.name);
  }
  for (size_t p = 0; p < pairs.size(); ++p)
    for (bool turning : {false, true}) {
      motions.emplace_back(kMotions);
      for (int k = 0; k < kMotions; ++k) {
        const double s = 2 * M_PI * k / kMotions;
        if (p < faces.size()) {
          const Vector3d u = Vector3d(0.2 * std::cos(s), 0.2 * std::sin(s), 1).normalized();
          motions.back()[k] = sweep(tools::face_pose(faces[p], k, kMotions, 0, false), u, 0.5, k, turning);
        } else {  // through A's centre, from beyond the sum of the radii to as far past it
          double reach = 0;
          for (const auto* points : {&pairs[p].a, &pairs[p].b})
            for (const Vector3d& x : *points) reach = std::max(reach, x.norm());
          const Vector3d u = Vector3d(std::cos(s), std::sin(3 * s), 0.5 * std::cos(2 * s)).normalized();
          motions.back()[k] = sweep(Isometry3d::Identity(), u, 2.2 * reach, k, turning);
        }
      }
      for (Method method : kMethods)
        benchmark::RegisterBenchmark(
            ("TimeOfImpact/" + names[p] + (turning ? "/turning/" : "/translation/") + name(method)).c_str(), Impact,
            std::cref(pairs[p]), std::cref(motions.back()), turning, method);
    }
  return 0;
}();

}  // namespace
