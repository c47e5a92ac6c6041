// The operations of the instruction budgets (tests/budgets.tsv), on fixed inputs, for callgrind.
// Run under `valgrind --tool=callgrind --collect-atstart=no` (tests/budgets.py does): each
// operation's calls are collected between two client requests and dumped under its name, and
// this program prints "<name> <calls>" for each, so instructions per call = the dump's total /
// calls. Everything else (building shapes, trees, poses) is not collected. The kernels run at
// AVX2, which every supported host has and valgrind decodes (it does not run AVX-512), so the
// counts are the same on every host. Without valgrind the client requests do nothing: the
// program then only checks that every operation succeeds.
#include <minksum/minksum.hpp>
#include <valgrind/callgrind.h>

#include <cstdio>
#include <functional>
#include <tuple>
#include <string>
#include <vector>

#include "haptics/loop.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

bool g_ok = true;

// Counts `calls` calls of op(k), k = 0 .. calls - 1, under `name`. op returns false on a failure.
void measure(const std::string& name, int calls, const std::function<bool(int)>& op) {
  bool ok = true;
  CALLGRIND_TOGGLE_COLLECT;
  for (int k = 0; k < calls; ++k) ok &= op(k);
  CALLGRIND_TOGGLE_COLLECT;
  CALLGRIND_DUMP_STATS_AT(name.c_str());
  if (!ok) std::fprintf(stderr, "budgets: %s failed\n", name.c_str()), g_ok = false;
  std::printf("%s %d\n", name.c_str(), calls);
}

Isometry3d pose_of(const Box& b) { return Eigen::Translation3d(b.center) * Isometry3d(b.rotation); }

// A box moving about a box along the trajectory benchmark's path (in and out of contact), as
// boxes and as prepared shapes; the default level (Want::Witnesses) unless named.
void box_pairs() {
  Box a, body;
  a.half_extents = Vector3d(0.5, 0.35, 0.25), body.half_extents = Vector3d(0.3, 0.4, 0.2);
  a.rotation = tools::axis_angle(Vector3d(1, 2, 3), 0.4), a.center = Vector3d(0.1, -0.2, 0.3);
  const auto path = tools::trajectory(7, 1000, 0.7, 1.6, 0.02 * body.half_extents.norm());
  std::vector<Box> b(path.size(), body);
  for (size_t k = 0; k < path.size(); ++k) {
    const Isometry3d p = pose_of(a) * path[k];
    b[k].center = p.translation(), b[k].rotation = p.linear();
  }
  const int n = int(path.size());
  Proximity p;
  measure("box_box.cold", n, [&](int k) { return proximity(a, b[size_t(k)], p) == Status::Ok; });
  ProximityCache cache;
  measure("box_box.coherent", n, [&](int k) { return proximity(a, b[size_t(k)], cache, p) == Status::Ok; });
  measure("box_box.verdict", n, [&](int k) { return proximity(a, b[size_t(k)], p, Want::Verdict) == Status::Ok; });
  ProximityCache patch_cache;
  measure("box_box.coherent.patch", n,
          [&](int k) { return proximity(a, b[size_t(k)], patch_cache, p, Want::Patch) == Status::Ok; });
  ConvexShape A, B;  // (A keeps its box's pose, B is placed by each call)
  shape_from_box(a, A), shape_from_box(body, B);
  measure("box_box_shapes.cold", n,
          [&](int k) { return proximity(A, Isometry3d::Identity(), B, pose_of(b[size_t(k)]), p) == Status::Ok; });
  ProximityCache shape_cache;
  measure("box_box_shapes.coherent", n, [&](int k) {
    return proximity(A, Isometry3d::Identity(), B, pose_of(b[size_t(k)]), shape_cache, p) == Status::Ok;
  });
}

// Table 1's icosahedron about its dodecahedron (prepared shapes), in and out of contact.
void convex_pairs() {
  ConvexShape A, B;
  // (The pyritohedron of integer coordinates near unit size: a regular dodecahedron's rounded
  // corners are not coplanar, and their exact hull has triangles.)
  shape_from_points(tools::scaled(tools::exact_dodecahedron_points(), 1.0 / 1024), A);
  shape_from_points(tools::icosahedron_points(), B);
  const Isometry3d pose_a(Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.4, Vector3d::UnitY()));
  const double r = 1156.0 / 1024 * std::sqrt(3.0) + std::sqrt(1 + 1.618034 * 1.618034);  // (the two radii)
  const auto path = tools::trajectory(11, 1000, 0.85 * r, 1.5 * r, 0.02 * std::sqrt(3.0));
  Proximity p;
  const int n = int(path.size());
  measure("convex.cold", n, [&](int k) { return proximity(A, pose_a, B, pose_a * path[size_t(k)], p) == Status::Ok; });
  ProximityCache cache;
  measure("convex.coherent", n,
          [&](int k) { return proximity(A, pose_a, B, pose_a * path[size_t(k)], cache, p) == Status::Ok; });
}

// Face on face, sliding and rocking: boxes (shape_from_box), 16-gon prisms and a box on a
// prism's cap, apart (1e-3), touching and pressed (1e-3 deep), cold and coherent; and the
// contact patch of the touching boxes and prisms.
void face_to_face() {
  for (const auto& f : tools::face_pairs()) {
    if (f.name != "prisms16" && f.name != "boxes" && f.name != "box_on_prism") continue;
    ConvexShape A, B;
    if (f.a_is_box ? shape_from_box(f.box_a, A) != Status::Ok : shape_from_points(f.a, A) != Status::Ok) g_ok = false;
    if (f.b_is_box ? shape_from_box(f.box_b, B) != Status::Ok : shape_from_points(f.b, B) != Status::Ok) g_ok = false;
    constexpr int n = 200;
    const Isometry3d I = Isometry3d::Identity();
    for (const auto& [band, gap] : {std::pair{"apart", 1e-3}, {"touching", 0.0}, {"pressed", -1e-3}}) {
      std::vector<Isometry3d> pose(n);
      for (int k = 0; k < n; ++k) pose[size_t(k)] = tools::face_pose(f, k, n, gap, true);
      const std::string name = "face." + f.name + "." + band;
      Proximity p;
      ProximityCache cache;
      measure((name + ".cold").c_str(), n, [&](int k) { return proximity(A, I, B, pose[size_t(k)], p) == Status::Ok; });
      measure((name + ".coherent").c_str(), n,
              [&](int k) { return proximity(A, I, B, pose[size_t(k)], cache, p) == Status::Ok; });
      ContactPatch patch;
      if (gap == 0 && f.name != "box_on_prism")
        measure(("patch." + f.name + ".touching").c_str(), n, [&](int k) {
          return contact_patch(A, I, B, pose[size_t(k)], 0, patch) == Status::Ok && patch.size > 0;
        });
    }
  }
}

// An icosahedron crossing a box within a tick, translating and turning.
void impacts() {
  ConvexShape A, B;
  shape_from_box(Box{}, A), shape_from_points(tools::scaled(tools::icosahedron_points(), 0.5), B);
  const Isometry3d I = Isometry3d::Identity();
  constexpr int n = 64;
  TimeOfImpact t;
  const auto motion = [](int k, bool turning, Isometry3d& b0, Isometry3d& b1) {
    const double s = 2 * M_PI * k / n;
    const Vector3d u = Vector3d(std::cos(s), std::sin(s), 0.3 * std::sin(2 * s)).normalized();
    b0 = Eigen::Translation3d(4 * u) * Isometry3d::Identity(), b1 = Eigen::Translation3d(-4 * u) * Isometry3d::Identity();
    if (turning) b1.linear() = tools::axis_angle(Vector3d(std::sin(s), 1, std::cos(s)), 0.5);
  };
  for (bool turning : {false, true})
    measure(turning ? "time_of_impact.turning" : "time_of_impact.translating", n, [&](int k) {
      Isometry3d b0, b1;
      motion(k, turning, b0, b1);
      return time_of_impact(A, I, I, B, b0, b1, t) == Status::Ok && t.hit;
    });
}

// Rounded shapes along the convex pairs' kind of path (in and out of contact): a sphere and a
// capsule against an icosahedron, cold and coherent; two capsules; a sphere or a capsule and a
// box (closed forms); two rounded boxes, coherent; a capsule crossing a box within a tick.
void rounded_shapes() {
  ConvexShape sphere, capsule, icosa, box, rounded_box, core;
  shape_from_sphere(0.5, sphere), shape_from_capsule(0.6, 0.3, capsule);
  shape_from_points(tools::scaled(tools::icosahedron_points(), 0.5), icosa);
  Box b;
  b.half_extents = Vector3d(0.5, 0.4, 0.3);
  shape_from_box(b, box), shape_from_box(b, core), shape_with_radius(core, 0.1, rounded_box);
  const Isometry3d I = Isometry3d::Identity();
  const auto path = tools::trajectory(13, 1000, 0.6, 1.8, 0.02);
  const int n = int(path.size());
  Proximity p;
  const auto pair = [&](const std::string& name, const ConvexShape& A, const ConvexShape& B, bool cold, bool coherent) {
    if (cold) measure(name + ".cold", n, [&](int k) { return proximity(A, I, B, path[size_t(k)], p) == Status::Ok; });
    ProximityCache cache;
    if (coherent)
      measure(name + ".coherent", n,
              [&](int k) { return proximity(A, I, B, path[size_t(k)], cache, p) == Status::Ok; });
  };
  pair("rounded.sphere_polytope", sphere, icosa, true, true);
  pair("rounded.capsule_polytope", capsule, icosa, true, true);
  pair("rounded.capsule_capsule", capsule, capsule, true, false);
  pair("rounded.sphere_box", sphere, box, true, false);
  pair("rounded.capsule_box", capsule, box, true, false);
  pair("rounded.rounded_boxes", rounded_box, rounded_box, false, true);
  TimeOfImpact t;
  constexpr int m = 64;
  measure("rounded.time_of_impact.capsule_box", m, [&](int k) {
    const double s = 2 * M_PI * k / m;
    const Vector3d u = Vector3d(std::cos(s), std::sin(s), 0.3 * std::sin(2 * s)).normalized();
    const Isometry3d c0 = Eigen::Translation3d(4 * u) * Isometry3d::Identity(),
                     c1 = Eigen::Translation3d(-4 * u) * Isometry3d::Identity();
    return time_of_impact(box, I, I, capsule, c0, c1, t) == Status::Ok && t.hit;
  });
}

// A 20 x 16 x 12 mm box against a generated bumpy sphere the size of the full bunny (the same
// mesh on every host), cold, at poses near and far.
void meshes() {
  const tools::Mesh scene = tools::bumpy_sphere(132);
  tools::Mesh tool;
  for (const Vector3d& p : tools::cube_points()) tool.vertices.emplace_back(0.01 * p.x(), 0.008 * p.y(), 0.006 * p.z());
  tool.triangles = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
                    {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
  Octree A, B;
  OctreeOptions one_leaf;
  one_leaf.max_depth = 0;
  if (build_octree(scene.vertices, scene.triangles, A) != Status::Ok ||
      build_octree(tool.vertices, tool.triangles, B, one_leaf) != Status::Ok)
    g_ok = false;
  MeshWorkspace ws;
  make_workspace(A, B, ws);
  const auto path = tools::trajectory(13, 100, 0.1, 0.2, 0.002);
  MeshDistance d;
  measure("mesh_distance.cold", int(path.size()), [&](int k) {
    return mesh_distance(A, Isometry3d::Identity(), B, path[size_t(k)], ws, d) == Status::Ok;
  });
  // A 5 mm sphere and a capsule (10 mm half length, 4 mm radius) along the same path: the shape
  // form of mesh_distance, cold and seeded by the last answer.
  ConvexShape ball, capsule;
  if (shape_from_sphere(0.005, ball) != Status::Ok || shape_from_capsule(0.01, 0.004, capsule) != Status::Ok) g_ok = false;
  for (const auto& [name, shape] : {std::pair<const char*, const ConvexShape*>{"sphere", &ball}, {"capsule", &capsule}}) {
    const std::string row = std::string("rounded.mesh_distance.") + name;
    measure(row + ".cold", int(path.size()), [&, shape = shape](int k) {
      return mesh_distance(A, Isometry3d::Identity(), *shape, path[size_t(k)], d) == Status::Ok;
    });
    ProximityCache cache;
    measure(row + ".coherent", int(path.size()), [&, shape = shape](int k) {
      return mesh_distance(A, Isometry3d::Identity(), *shape, path[size_t(k)], cache, d) == Status::Ok;
    });
  }
  // Mesh contact of the sphere, the capsule and the box tool with a 2 mm radius, each pressed
  // 1 mm into the mesh from the path's poses (moved along their nearest pair).
  ConvexShape box_core, rounded_box;
  if (shape_from_points(tool.vertices, box_core) != Status::Ok || shape_with_radius(box_core, 0.002, rounded_box) != Status::Ok)
    g_ok = false;
  MeshContact c;
  for (const auto& [name, shape] : {std::pair<const char*, const ConvexShape*>{"sphere", &ball}, {"capsule", &capsule},
                                    {"rounded_box", &rounded_box}}) {
    std::vector<Isometry3d> pressed = path;
    for (Isometry3d& at : pressed)
      if (mesh_distance(A, Isometry3d::Identity(), *shape, at, d) == Status::Ok && !d.intersecting)
        at.pretranslate((d.point_a - d.point_b) * (1 + 0.001 / d.distance));
    measure(std::string("rounded.mesh_contact.") + name, int(pressed.size()), [&, shape = shape](int k) {
      return mesh_contact(A, Isometry3d::Identity(), *shape, pressed[size_t(k)], ws, c) == Status::Ok && c.intersecting;
    });
  }
  // A tool the size of the mesh (an icosahedron 0.18 across) swept through it: starting across
  // its surface (time 0), and starting clear, 0.15 above it.
  ConvexShape tool_shape;
  if (shape_from_points(tools::scaled(tools::icosahedron_points(), 0.09 / 1.902), tool_shape) != Status::Ok) g_ok = false;
  TimeOfImpact toi;
  const Isometry3d I = Isometry3d::Identity();
  for (const auto& [name, lift] : {std::pair{"mesh_sweep.starting_in_contact", 0.09}, {"mesh_sweep.starting_clear", 0.25}})
    measure(name, 16, [&](int k) {
      const double s = 2 * M_PI * k / 16;
      const Vector3d u = Vector3d(std::cos(s), std::sin(s), 0.3).normalized();
      const Isometry3d t0 = Eigen::Translation3d(lift * u) * I, t1 = Eigen::Translation3d(-0.1 * u) * I;
      return time_of_impact(A, I, tool_shape, t0, t1, toi) == Status::Ok && toi.hit;
    });
}

// The haptic loop on the full bunny's stand-in (the box tool, and the default 5 mm sphere;
// 6-DOF, coherent): a run of 4,001 ticks (one cycle of the path: approach, press, slide
// turning, leave) less a run of 1, per tick.
void haptics_loop() {
  haptics::Options o;
  o.scene = "bumpy_full", o.warmup = 0;
  haptics::Report report;
  std::string error;
  for (const auto& [tool, row] : {std::pair<std::string, std::string>{"box", "haptic_tick"}, {"sphere:5", "haptic_tick_sphere"}}) {
    o.tool = tool;
    for (double seconds : {0.001, 4.001}) {
      o.seconds = seconds;
      CALLGRIND_TOGGLE_COLLECT;
      const bool ok = haptics::run(o, [] { return -1L; }, report, error);
      CALLGRIND_TOGGLE_COLLECT;
      const std::string dump = row + (seconds < 1 ? ".setup" : ".setup_and_4000");  // (alive through the macro)
      CALLGRIND_DUMP_STATS_AT(dump.c_str());
      if (!ok) std::fprintf(stderr, "budgets: haptics: %s\n", error.c_str()), g_ok = false;
    }
    std::printf("%s 4000 = %s.setup_and_4000 - %s.setup\n", row.c_str(), row.c_str(), row.c_str());
  }
}

// The sum of each Table 1 pair (prepared shapes, as given and B turned), of aligned rounded prisms, and
// the box-box kernel's whole polytopes of 32 box pairs.
void sums() {
  std::vector<std::pair<ConvexShape, ConvexShape>> shapes;
  for (const auto& t : tools::table1_pairs()) {
    shapes.emplace_back();
    if (shape_from_points(t.a, shapes.back().first) != Status::Ok ||
        shape_from_points(t.b, shapes.back().second) != Status::Ok)
      g_ok = false;
  }
  MinkowskiSum m;
  const Isometry3d I = Isometry3d::Identity();
  for (const auto& [a, b] : shapes) minkowski_sum(a, I, b, I, m);  // (grows m to its size first)
  measure("sum.table1", int(shapes.size()), [&](int k) {
    return minkowski_sum(shapes[size_t(k)].first, I, shapes[size_t(k)].second, I, m) == Status::Ok;
  });
  // The same pairs in the report's pose (B turned: no tie, so the small overlay's tables answer),
  // the whole polytope, the vertices level and the planes level.
  std::vector<std::pair<ConvexShape, ConvexShape>> turned;
  Isometry3d pose_b = I;
  for (const auto& t : tools::table1_pairs()) {
    turned.emplace_back();
    if (shape_from_points(t.a, turned.back().first) != Status::Ok ||
        shape_from_points(t.b_body, turned.back().second) != Status::Ok)
      g_ok = false;
    pose_b.linear() = t.rotation;  // (one turn for every pair)
  }
  for (const SumParts parts : {SumParts::Whole, SumParts::Vertices, SumParts::Planes}) {
    for (const auto& [a, b] : turned) minkowski_sum(a, I, b, pose_b, m, parts);
    const char* name = parts == SumParts::Whole      ? "sum.table1.turned"
                       : parts == SumParts::Vertices ? "sum.table1.turned.vertices"
                                                     : "sum.table1.turned.planes";
    measure(name, int(turned.size()),
            [&](int k) {
              const auto& [a, b] = turned[size_t(k)];
              return minkowski_sum(a, I, b, pose_b, m, parts) == Status::Ok;
            });
  }
  // The same pairs in one frame, B a rounded copy of its body (its points turned by
  // table1_rotation() and back), so where A and B are one solid (icosa_icosa, dodeca_dodeca)
  // every face of B lies within rounding of A's (split into triangles where its rounded corners
  // left it): each sign near a face is a near-tie (the double-double stage of orient_exact
  // decides them).
  const Eigen::Matrix3d R = tools::table1_rotation();
  std::vector<std::pair<ConvexShape, ConvexShape>> back;
  for (const auto& t : tools::table1_pairs()) {
    back.emplace_back();
    if (shape_from_points(t.a, back.back().first) != Status::Ok ||
        shape_from_points(tools::rotated(tools::rotated(t.b_body, R), R.transpose()), back.back().second) != Status::Ok)
      g_ok = false;
  }
  for (const auto& [a, b] : back) minkowski_sum(a, I, b, I, m);
  measure("sum.table1.turned_back", int(back.size()), [&](int k) {
    const auto& [a, b] = back[size_t(k)];
    return minkowski_sum(a, I, b, I, m) == Status::Ok;
  });
  // Aligned cos/sin prisms of 64 sides (rounded coordinates: their parallel sides are ties the
  // expansions decide), summed first for their pair in the thread (B's two copies in turn, so
  // no memo of ties is kept) and again (the memo kept: Overlay::run).
  // The same for an icosahedron and a rounded copy of another size (near-ties: the normals to
  // 106 bits are kept per face, Placed::near).
  const auto rounded = tools::rounded_pairs();
  for (const auto& [index, name] : {std::pair<int, const char*>{3, "sum.rounded_prisms64"}, {7, "sum.icosa_copies"}}) {
    const tools::DegeneratePair& pair = rounded[size_t(index)];
    ConvexShape shape_a, shape_b[2];
    if (shape_from_points(pair.a, shape_a) != Status::Ok || shape_from_points(pair.b, shape_b[0]) != Status::Ok ||
        shape_from_points(pair.b, shape_b[1]) != Status::Ok)
      g_ok = false;
    const auto rounded_sum = [&](int copy) { return minkowski_sum(shape_a, I, shape_b[copy], I, m) == Status::Ok; };
    rounded_sum(1);
    measure(std::string(name) + ".first", 4, [&](int k) { return rounded_sum(k % 2); });
    measure(std::string(name) + ".again", 4, [&](int) { return rounded_sum(1); });
  }
  // Rounded sums: a sphere and a box (the box translated), a rounded box and an icosahedron
  // turned (the cores' overlay), each read back by contains.
  ConvexShape sphere, box, rounded_box, icosa;
  shape_from_sphere(0.25, sphere), shape_from_box(Box{}, box), shape_with_radius(box, 0.1, rounded_box);
  shape_from_points(tools::icosahedron_points(), icosa);
  const Isometry3d moved = Eigen::Translation3d(0.5, 0.25, 0) * Isometry3d(tools::axis_angle(Vector3d(1, 2, 3), 0.4));
  for (const auto& [name, a, b] : {std::tuple{"rounded.sum.sphere_box", &sphere, &box},
                                   std::tuple{"rounded.sum.rounded_box_icosa", &rounded_box, &icosa}})
    measure(name, 4, [&, a = a, b = b](int k) {
      return minkowski_sum(*a, I, *b, moved, m) == Status::Ok && contains(m, Vector3d(0.1 * k, 0, 1.2));
    });
  static BoxBatch<double, 32> A, B;
  static BoxBoxSum<double, 32> out;
  tools::fill_table1_cubes(A, B);
  measure("box_box_kernel.sum_of_32", 1, [&](int) { return box_box_sum(A, B, out), true; });
}

}  // namespace

// The hull step of shapes from points: polytope_from_points on the Table 1 operands (cube,
// icosahedron, dodecahedron), per operand.
void hulls() {
  const auto pairs = tools::table1_pairs();
  const std::vector<Vector3d> operands[] = {pairs[0].a, pairs[1].b, pairs[4].b};
  ConvexPolytope P;
  measure("hull.table1", 3, [&](int k) { return polytope_from_points(operands[k], P) == Status::Ok; });
}

int main() {
  if (!force_isa(Isa::Avx2)) {
    std::fprintf(stderr, "budgets: this CPU has no AVX2 (the budgets are counted at AVX2)\n");
    return 2;
  }
  box_pairs();
  convex_pairs();
  face_to_face();
  impacts();
  rounded_shapes();
  meshes();
  haptics_loop();
  sums();
  hulls();
  return g_ok ? 0 : 1;
}
