// Time of impact (time_of_impact) against brute force (test::brute_force on the explicitly
// placed polytopes). Pure translation: the first contact by bisection on the overlap (the
// times of overlap of a translating pair are one interval), to which the answer must be equal
// to rounding and never after. With rotation: the shapes are apart at every one of 500
// sampled times before the answer, and within the tolerance at it; no hit means apart at every
// sampled time. A thin sheet swept by a small tool at 1, 3 and 10 m/s in a 1 ms tick, the tool
// clear of it at both ends: every sweep must hit.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <array>
#include <cmath>
#include <random>

#include "checks.hpp"
#include "ties.hpp"
#include "support/mesh_io.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector3d;

// The pose of a motion at t as time_of_impact takes it (its own interpolation, written again).
Isometry3d at(const Isometry3d& p0, const Isometry3d& p1, double t) {
  const Eigen::AngleAxisd turn(Eigen::Matrix3d(p0.linear().transpose() * p1.linear()));
  Isometry3d p = Isometry3d::Identity();
  p.linear() = p0.linear() * Eigen::AngleAxisd(t * turn.angle(), turn.axis()).toRotationMatrix();
  p.translation() = (1 - t) * p0.translation() + t * p1.translation();
  return p;
}

test::Oracle oracle(const ConvexShape& a, const Isometry3d& pa, const ConvexShape& b, const Isometry3d& pb) {
  return test::brute_force(test::transformed(a.polytope(), pa), test::transformed(b.polytope(), pb));
}

const Isometry3d kIdentity = Isometry3d::Identity();

// The gap along n between A's highest vertex and B's lowest: the normal of an answer at time
// > 0 must separate them to within its tolerance (0 <= gap <= distance <= tolerance).
double gap_along(const ConvexShape& a, const Isometry3d& pa, const ConvexShape& b, const Isometry3d& pb,
                 const Vector3d& n) {
  double top = -HUGE_VAL, bottom = HUGE_VAL;
  for (const Vector3d& x : a.polytope().vertices) top = std::max(top, n.dot(pa * x));
  for (const Vector3d& x : b.polytope().vertices) bottom = std::min(bottom, n.dot(pb * x));
  return bottom - top;
}

// The public motion is the one the sweeps take: against Eigen's quaternion slerp and a linear
// translation (the loop's proxy is placed by it), its ends the poses given, and a hit's pose
// from it touching (a box falling turning onto a box: the gap at the hit within the tolerance).
TEST(TimeOfImpact, MotionIsSlerpAndTheSweepsPath) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> unit(0, 1);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Isometry3d a = test::random_pose(rng, 2), b = test::random_pose(rng, 2);
    const Motion m{a, b};
    const double t = k < 2 ? double(k) : unit(rng);
    const Eigen::Isometry3d p = m.at(t);
    const Eigen::Quaterniond qa(a.linear()), qb(b.linear());
    EXPECT_LT((p.linear() - qa.slerp(t, qb).toRotationMatrix()).norm(), 1e-12) << k;
    EXPECT_LT((p.translation() - (a.translation() + t * (b.translation() - a.translation()))).norm(), 1e-12) << k;
  }
  ConvexShape box;
  ASSERT_EQ(shape_from_box(Box{}, box), Status::Ok);
  Eigen::Isometry3d b0 = Eigen::Isometry3d::Identity(), b1 = b0;
  b0.translation() = Eigen::Vector3d(0.2, 0.1, 4), b1.translation() = Eigen::Vector3d(0.2, 0.1, -1);
  b1.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix();
  TimeOfImpact toi;
  const Eigen::Isometry3d I = Eigen::Isometry3d::Identity();
  ASSERT_EQ(time_of_impact(box, I, I, box, b0, b1, toi), Status::Ok);
  ASSERT_TRUE(toi.hit);
  Proximity p;
  ASSERT_EQ(proximity(box, I, box, Motion{b0, b1}.at(toi.time), p), Status::Ok);
  EXPECT_LE(p.intersecting ? 0.0 : p.distance, toi.tolerance);
  EXPECT_FALSE(p.intersecting && p.penetration_depth > toi.tolerance);
}

TEST(TimeOfImpact, TranslationEqualsBisection) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> unit(-1, 1);
  int hits = 0, misses = 0;
  const int pairs = test::scaled(150);
  for (int k = 0; k < pairs; ++k) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(tools::sphere_points(12 + k % 20, 300 + k), A), Status::Ok);
    ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(8 + k % 9, 900 + k), 0.6), B), Status::Ok);
    const Isometry3d pa(Eigen::AngleAxisd(unit(rng), Vector3d(1, 2, 3).normalized()));
    const Eigen::Matrix3d rb = Eigen::AngleAxisd(unit(rng), Vector3d(3, -1, 2).normalized()).toRotationMatrix();
    // B from 3 away towards A's neighbourhood (a random aim: some pass by), A still.
    const Vector3d from = 3 * Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    // (Every fourth passes 1.9 from A's centre, beyond the two radii: a miss.)
    const Vector3d side = from.cross(Vector3d(unit(rng), unit(rng), unit(rng))).normalized();
    const Vector3d to = -from + (k % 4 == 0 ? 5.0 * side : 1.5 * Vector3d(unit(rng), unit(rng), unit(rng)));
    Isometry3d b0 = Isometry3d::Identity(), b1 = b0;
    b0.linear() = b1.linear() = rb, b0.translation() = from, b1.translation() = to;
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(A, pa, pa, B, b0, b1, toi), Status::Ok);
    const std::string where = "pair " + std::to_string(k);
    ASSERT_TRUE(toi.converged) << where;
    EXPECT_LE(toi.distance, toi.tolerance) << where;
    // The overlap along the segment, sampled; its first time by bisection.
    double inside = -1;
    for (int s = 0; s <= 200 && inside < 0; ++s)
      if (oracle(A, pa, B, at(b0, b1, s / 200.0)).overlap) inside = s / 200.0;
    if (inside < 0) {  // (a contact shorter than 1/200 of the tick may be missed by the samples)
      if (!toi.hit) ++misses;
      continue;
    }
    ASSERT_TRUE(toi.hit) << where;
    double lo = 0, hi = inside;
    for (int s = 0; s < 60; ++s) (oracle(A, pa, B, at(b0, b1, (lo + hi) / 2)).overlap ? hi : lo) = (lo + hi) / 2;
    // Exact to rounding: within 1e-9 of the tick (the stop is 1e-12 of the size, at speeds near 1).
    EXPECT_NEAR(toi.time, lo, 1e-9) << where;
    EXPECT_LE(toi.time, hi + 1e-12) << where << " (after the first contact)";
    const test::Oracle o = oracle(A, pa, B, at(b0, b1, toi.time));
    EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance + 1e-12) << where;
    EXPECT_NEAR(toi.normal.norm(), 1, 1e-12) << where;
    const double g = gap_along(A, pa, B, at(b0, b1, toi.time), toi.normal);
    EXPECT_GE(g, -1e-12) << where;
    EXPECT_LE(g, toi.tolerance + 1e-12) << where;
    ++hits;
  }
  EXPECT_GT(hits, pairs / 3);
  EXPECT_GT(misses, 0);
}

TEST(TimeOfImpact, RotationNeverReportsAfterTheFirstContact) {
  std::mt19937_64 rng(47);
  std::uniform_real_distribution<double> unit(-1, 1);
  int hits = 0;
  const int pairs = test::scaled(60);
  for (int k = 0; k < pairs; ++k) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(tools::sphere_points(10 + k % 12, 500 + k), A), Status::Ok);
    ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(6 + k % 7, 1100 + k), 0.5), B), Status::Ok);
    const Vector3d from = 2.5 * Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
    const Isometry3d a0(Eigen::AngleAxisd(unit(rng), Vector3d(0, 1, 0)));
    const Isometry3d a1 = a0 * Eigen::AngleAxisd(0.5 * unit(rng), Vector3d(1, 0, 0));
    const Isometry3d b0 = Eigen::Translation3d(from) * Eigen::AngleAxisd(3 * unit(rng), Vector3d(1, 1, 0).normalized());
    const Isometry3d b1 = Eigen::Translation3d(-0.4 * from + 0.6 * Vector3d(unit(rng), unit(rng), unit(rng))) *
                          Eigen::AngleAxisd(3 * unit(rng), Vector3d(0, 1, 1).normalized());
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(A, a0, a1, B, b0, b1, toi), Status::Ok);
    const std::string where = "pair " + std::to_string(k);
    ASSERT_TRUE(toi.converged) << where;
    const double end = toi.hit ? toi.time : 1.0;
    for (int s = 0; s < 500; ++s) {
      const double t = end * s / 500.0;
      EXPECT_FALSE(oracle(A, at(a0, a1, t), B, at(b0, b1, t)).overlap) << where << " t " << t;
    }
    if (!toi.hit) continue;
    ++hits;
    const test::Oracle o = oracle(A, at(a0, a1, toi.time), B, at(b0, b1, toi.time));
    EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << where;
    const double g = gap_along(A, at(a0, a1, toi.time), B, at(b0, b1, toi.time), toi.normal);
    EXPECT_GE(g, -1e-12) << where;
    EXPECT_LE(g, toi.tolerance * (1 + 1e-9)) << where;
  }
  EXPECT_GT(hits, pairs / 3);
}

TEST(TimeOfImpact, TurningOntoAFaceOnIntegerCoordinates) {
  // Ties everywhere: a box or an octahedron (integer corners) falls turning onto a box's top
  // face (z = 0), about axes along, across and oblique to the faces (about z, B's bottom face
  // stays parallel to the top all along), by up to a half turn. Apart at 500 sampled times
  // before the answer (50 under the sanitizers), within the tolerance at it, the normal a
  // separating plane there; a quarter turn about z (the box's bottom face parallel to the top
  // face at every time) is a pure fall: the time is exact to within the tolerance, and not
  // after.
  ConvexShape A, box, octahedron;
  ASSERT_EQ(shape_from_box(Box{Vector3d(0, 0, -1), Eigen::Matrix3d::Identity(), Vector3d(3, 3, 1)}, A), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(1, 1, 1)}, box), Status::Ok);
  ASSERT_EQ(shape_from_points({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}, octahedron),
            Status::Ok);
  const Vector3d axes[] = {Vector3d::UnitZ(), Vector3d::UnitX(), Vector3d(1, 1, 0).normalized(),
                           Vector3d(1, 0, 1).normalized(), Vector3d(1, 2, 2).normalized()};
  const int samples = test::scaled(500, 50);  // (fewer under the sanitizers)
  for (const ConvexShape* B : {&box, &octahedron})
    for (const Vector3d& axis : axes)
      for (double angle : {0.25, M_PI / 2, 1.0, 3.0})
        for (int drop : {2, 3, 5}) {
          const Isometry3d b0 = Eigen::Translation3d(0, 0, 1 + drop) * Eigen::AngleAxisd(0, axis);
          const Isometry3d b1 = Eigen::Translation3d(0, 0, 1 - drop) * Eigen::AngleAxisd(angle, axis);
          const std::string where = std::string(B == &box ? "box" : "octahedron") + " axis " +
                                    std::to_string(&axis - axes) + " angle " + std::to_string(angle) + " drop " +
                                    std::to_string(drop);
          TimeOfImpact toi;
          ASSERT_EQ(time_of_impact(A, kIdentity, kIdentity, *B, b0, b1, toi), Status::Ok) << where;
          ASSERT_TRUE(toi.hit) << where;  // (it ends 2 below the top: through it)
          ASSERT_TRUE(toi.converged) << where;
          for (int s = 0; s < samples; ++s)
            EXPECT_FALSE(oracle(A, kIdentity, *B, at(b0, b1, toi.time * s / samples)).overlap) << where;
          const Isometry3d pb = at(b0, b1, toi.time);
          const test::Oracle o = oracle(A, kIdentity, *B, pb);
          EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << where;
          const double g = gap_along(A, kIdentity, *B, pb, toi.normal);
          EXPECT_GE(g, -1e-12) << where;
          EXPECT_LE(g, toi.tolerance * (1 + 1e-9)) << where;
          if (B == &box && &axis == axes && angle == M_PI / 2) {  // touching at 1/2, closing at 2 drop
            EXPECT_LE(toi.time, 0.5) << where;
            EXPECT_GE(toi.time, 0.5 - toi.tolerance / (2.0 * drop) - 1e-15) << where;
          }
        }
}

// The sheet's sweeps: a tool of 0.3 mm (its radius 0.15 mm) over a sheet 0.5 mm thick whose top
// is z = 0.25 mm, in metres; in a 1 ms tick at 1, 3 and 10 m/s the tool moves 1, 3 and 10 mm,
// from about 0.1 mm above the sheet to below it (clear of it at both ends), straight down or
// slanted, turning or not. `first`: when, translating, its lowest point reaches the top.
struct SheetSweep {
  Isometry3d t0, t1;
  bool turning;
  double first;
  std::string where;
};

std::vector<SheetSweep> sheet_sweeps(const ConvexShape& tool) {
  std::vector<SheetSweep> out;
  for (double speed : {1.0, 3.0, 10.0})
    for (int slant = 0; slant < 3; ++slant)
      for (bool turning : {false, true}) {
        const double step = speed * 1e-3;  // metres per tick
        const Vector3d down = Vector3d(0.2 * slant, 0.1 * slant, -1).normalized();
        const Vector3d start(0.01, -0.02, 0.25e-3 + 0.15e-3 + 0.1e-3);
        SheetSweep w;
        w.t0 = Eigen::Translation3d(start) * Eigen::AngleAxisd(0.3, Vector3d::UnitX());
        w.t1 = Eigen::Translation3d(start + step * down) * Eigen::AngleAxisd(0.3 + (turning ? 2.0 : 0.0), Vector3d::UnitX());
        w.turning = turning;
        double low = HUGE_VAL;
        for (const Vector3d& v : tool.polytope().vertices) low = std::min(low, (w.t0 * v).z());
        w.first = (low - 0.25e-3) / (-down.z() * step);
        w.where = "speed " + std::to_string(speed) + " slant " + std::to_string(slant) + (turning ? " turning" : "");
        out.push_back(w);
      }
  return out;
}

TEST(TimeOfImpact, NoTunnellingThroughAThinSheet) {
  // The sheet 20 cm wide as a box; every sweep must hit, at the first touch translating; apart
  // before it and within the tolerance at it turning.
  ConvexShape sheet, tool;
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(0.1, 0.1, 0.25e-3)}, sheet),
            Status::Ok);
  ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(16, 7), 0.15e-3), tool), Status::Ok);
  const std::vector<SheetSweep> sweeps = sheet_sweeps(tool);
  ASSERT_EQ(sweeps.size(), 18u);
  for (const SheetSweep& w : sweeps) {
    ASSERT_FALSE(oracle(sheet, kIdentity, tool, w.t0).overlap) << w.where;
    ASSERT_FALSE(oracle(sheet, kIdentity, tool, w.t1).overlap) << w.where << " (the tool must end clear)";
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(sheet, kIdentity, kIdentity, tool, w.t0, w.t1, toi), Status::Ok) << w.where;
    EXPECT_TRUE(toi.hit) << w.where;
    EXPECT_TRUE(toi.converged) << w.where;
    if (!w.turning) EXPECT_NEAR(toi.time, w.first, 1e-9) << w.where;
    for (int s = 0; s < 200; ++s)
      EXPECT_FALSE(oracle(sheet, kIdentity, tool, at(w.t0, w.t1, toi.time * s / 200)).overlap) << w.where;
    const test::Oracle o = oracle(sheet, kIdentity, tool, at(w.t0, w.t1, toi.time));
    EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << w.where;
    EXPECT_GT(toi.normal.z(), 0.9) << w.where;  // the sheet's top, towards the tool
  }
}

// A terrain of n x n cells over [-1, 1]^2, two triangles each, at heights in steps of 1/4
// (flat runs and parallel faces: ties), and its triangles as shapes (the oracle's).
void terrain(int n, std::vector<Vector3d>& vertices, std::vector<std::array<int, 3>>& triangles) {
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) vertices.emplace_back(-1 + 2.0 * i / n, -1 + 2.0 * j / n, 0.25 * ((7 * i + 3 * j) % 3));
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const int v = i * (n + 1) + j;
      triangles.push_back({v, v + n + 1, v + 1}), triangles.push_back({v + 1, v + n + 1, v + n + 2});
    }
}

TEST(TimeOfImpact, AMeshEqualsTheEarliestOfItsTriangles) {
  // A tool falls onto the terrain, slanted, turning or not: the mesh's answer must be the
  // earliest of the tool against each triangle alone (time_of_impact on the triangle as a
  // shape), to within the tolerance's time; never after the first contact (apart at 100
  // sampled times before it, by brute force against every triangle); within the tolerance
  // of the mesh at it.
  std::vector<Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  terrain(6, vertices, triangles);
  Octree mesh;
  ASSERT_EQ(build_octree(vertices, triangles, mesh, OctreeOptions{4}), Status::Ok);
  std::vector<ConvexShape> pieces(triangles.size());
  for (size_t k = 0; k < triangles.size(); ++k)
    ASSERT_EQ(shape_from_triangle({vertices[triangles[k][0]], vertices[triangles[k][1]], vertices[triangles[k][2]]},
                                  pieces[k]),
              Status::Ok);
  ConvexShape tool;
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(0.2, 0.15, 0.1)}, tool),
            Status::Ok);
  std::mt19937_64 rng(53);
  std::uniform_real_distribution<double> unit(-1, 1);
  const Isometry3d place(Eigen::Translation3d(0.5, -0.25, 0.125));  // the mesh's pose
  int hits = 0, misses = 0;
  const int sweeps = test::scaled(80);
  for (int k = 0; k < sweeps; ++k) {
    const bool turning = k % 2 == 1;
    const Vector3d from(0.8 * unit(rng), 0.8 * unit(rng), 1.2), to = from + Vector3d(unit(rng), unit(rng), -2.0);
    // (Every fifth sweep passes above the terrain: a miss.)
    const Vector3d end = k % 5 == 0 ? Vector3d(to.x(), to.y(), 0.9) : to;
    const Isometry3d t0 = place * Eigen::Translation3d(from) * Eigen::AngleAxisd(unit(rng), Vector3d(1, 2, 0).normalized());
    const Isometry3d t1 = place * Eigen::Translation3d(end) *
                          Eigen::AngleAxisd(unit(rng) + (turning ? 1.5 : 0.0), Vector3d(1, 2, 0).normalized());
    const double tolerance = turning ? 1e-7 : 1e-11;
    const std::string where = "sweep " + std::to_string(k);
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(mesh, place, tool, t0, t1, toi, tolerance), Status::Ok) << where;
    ASSERT_TRUE(toi.converged) << where;
    double first = 1;
    int first_triangle = -1;
    for (size_t j = 0; j < pieces.size(); ++j) {
      TimeOfImpact one;
      ASSERT_EQ(time_of_impact(pieces[j], place, place, tool, t0, t1, one, tolerance), Status::Ok);
      if (one.hit && one.time < first) first = one.time, first_triangle = int(j);
    }
    EXPECT_EQ(toi.hit, first_triangle >= 0) << where;
    if (!toi.hit) {
      ++misses;
      continue;
    }
    ++hits;
    // Both stop within the tolerance short of the contact: at speeds near 2 per tick, their
    // times differ by at most the tolerance's time.
    EXPECT_NEAR(toi.time, first, 1e-6) << where;
    const Isometry3d at_hit = at(t0, t1, toi.time);
    double nearest = HUGE_VAL;
    for (const ConvexShape& piece : pieces) {
      const test::Oracle o = oracle(piece, place, tool, at_hit);
      nearest = std::min(nearest, o.overlap ? 0.0 : o.distance);
    }
    EXPECT_LE(nearest, tolerance * (1 + 1e-6)) << where;
    EXPECT_GE(toi.triangle, 0) << where;
    for (int s = 0; s < 100; ++s)
      for (const ConvexShape& piece : pieces)
        ASSERT_FALSE(oracle(piece, place, tool, at(t0, t1, toi.time * s / 100)).overlap) << where << " sample " << s;
  }
  EXPECT_GT(hits, sweeps / 2);
  EXPECT_GT(misses, 0);
}

TEST(TimeOfImpact, AMeshSweepThatStartsInContactStopsAtOnce) {
  // A tool about the size of the mesh, starting across its surface (so in contact with
  // hundreds of its triangles), translating or turning: time 0, at a triangle the tool meets
  // at the start (exact distance within the tolerance), after the advancement of a few
  // triangles, not of every one the tool covers (the iterations count them: GJK steps, no
  // clock). Turning in place, the triangles it reaches later in the tick can fill the heap
  // before the walk opens the leaf it touches at once: those are advanced first.
  const tools::Mesh ball = tools::bumpy_sphere(40);  // 6,400 triangles, 0.19 across
  Octree mesh;
  ASSERT_EQ(build_octree(ball.vertices, ball.triangles, mesh), Status::Ok);
  ConvexShape tool;
  ASSERT_EQ(shape_from_points(tools::scaled(tools::icosahedron_points(), 0.05), tool), Status::Ok);
  const Isometry3d I = Isometry3d::Identity();
  for (int k = 0; k < 8; ++k) {
    const double s = 2 * M_PI * k / 8;
    const Vector3d at = 0.09 * Vector3d(std::cos(s), std::sin(s), 0.3 * std::sin(3 * s)).normalized();
    const Isometry3d t0 = Eigen::Translation3d(at) * I;  // (odd k translating through, even k turning in place)
    const Isometry3d t1 = k % 2 ? Eigen::Translation3d(-at) * I : t0 * Eigen::AngleAxisd(1.0, Vector3d::UnitZ());
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(mesh, I, tool, t0, t1, toi), Status::Ok) << k;
    ASSERT_TRUE(toi.hit && toi.converged) << k;
    EXPECT_EQ(toi.time, 0) << k;
    ASSERT_GE(toi.triangle, 0) << k;
    const auto& t = ball.triangles[size_t(toi.triangle)];
    ConvexShape piece;
    ASSERT_EQ(shape_from_triangle({ball.vertices[t[0]], ball.vertices[t[1]], ball.vertices[t[2]]}, piece), Status::Ok);
    const test::Oracle o = oracle(piece, I, tool, t0);
    EXPECT_TRUE(o.overlap || o.distance <= toi.tolerance) << k;
    EXPECT_LT(toi.iterations, 300) << k;  // (4-5 on 7 of these poses, 201 on one; 4,357-4,977 before the walk stopped at a hit at 0)
  }
}

// A box beside a mesh triangle's edge, within the tolerance of it at the start: a hit at 0, and
// its normal separates them (to the tolerance), as the normal of every hit must. Here that is
// -x, from the triangle to the box; the triangle's own normal (+z towards the box, the normal
// before) has the box 0.3 below the triangle's plane along it, a plane through the box.
TEST(TimeOfImpact, AMeshHitAtTheStartHasASeparatingNormal) {
  Octree mesh;
  ASSERT_EQ(build_octree({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}}, mesh), Status::Ok);
  Box half;
  half.half_extents = Vector3d::Constant(0.5);
  ConvexShape box;
  ASSERT_EQ(shape_from_box(half, box), Status::Ok);
  const double tolerance = 1e-6;
  for (const double turn : {0.0, 0.3}) {
    const Isometry3d t0(Eigen::Translation3d(-0.5 - tolerance / 4, 0.3, 0.2));
    Isometry3d t1 = t0;
    t1.translation().x() += 0.1;
    t1.linear() = Eigen::AngleAxisd(turn, Vector3d::UnitZ()).toRotationMatrix();
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(mesh, kIdentity, box, t0, t1, toi, tolerance), Status::Ok);
    ASSERT_TRUE(toi.hit);
    EXPECT_EQ(toi.time, 0);
    EXPECT_NEAR(toi.normal.norm(), 1, 1e-12);
    double top = -HUGE_VAL, bottom = HUGE_VAL;  // the triangle's highest corner and the box's lowest along it
    for (const Vector3d& x : {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0)}) top = std::max(top, toi.normal.dot(x));
    for (const Vector3d& x : box.polytope().vertices) bottom = std::min(bottom, toi.normal.dot(t0 * x));
    EXPECT_GE(bottom - top, -tolerance) << "normal " << toi.normal.transpose();
  }
}

TEST(TimeOfImpact, NoTunnellingThroughAThinSheetMesh) {
  // The 0.5 mm sheet of NoTunnellingThroughAThinSheet as a mesh (its top and bottom split into
  // a 10 x 10 grid, and its four sides), swept by the same 0.3 mm tool at 1, 3 and 10 m/s.
  std::vector<Vector3d> vertices;
  std::vector<std::array<int, 3>> triangles;
  for (double z : {0.25e-3, -0.25e-3}) {
    const int base = int(vertices.size());
    for (int i = 0; i <= 10; ++i)
      for (int j = 0; j <= 10; ++j) vertices.emplace_back(-0.1 + 0.02 * i, -0.1 + 0.02 * j, z);
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) {
        const int v = base + i * 11 + j;
        if (z > 0)
          triangles.push_back({v, v + 11, v + 1}), triangles.push_back({v + 1, v + 11, v + 12});
        else
          triangles.push_back({v, v + 1, v + 11}), triangles.push_back({v + 1, v + 12, v + 11});
      }
  }
  const int corner[4] = {0, 10, 120, 110};  // the top's corners, counter-clockwise; the bottom's are 121 on
  for (int k = 0; k < 4; ++k) {
    const int a = corner[k], b = corner[(k + 1) % 4];
    triangles.push_back({a, a + 121, b}), triangles.push_back({b, a + 121, b + 121});
  }
  Octree sheet;
  ASSERT_EQ(build_octree(vertices, triangles, sheet), Status::Ok);
  ConvexShape tool;
  ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(16, 7), 0.15e-3), tool), Status::Ok);
  for (const SheetSweep& w : sheet_sweeps(tool)) {
    TimeOfImpact toi;
    ASSERT_EQ(time_of_impact(sheet, kIdentity, tool, w.t0, w.t1, toi), Status::Ok) << w.where;
    EXPECT_TRUE(toi.hit) << w.where;
    EXPECT_TRUE(toi.converged) << w.where;
    EXPECT_LE(toi.time, w.first + 1e-12) << w.where;
    if (!w.turning) EXPECT_NEAR(toi.time, w.first, 1e-9) << w.where;
    EXPECT_GT(toi.normal.z(), 0.9) << w.where;  // the sheet's top, towards the tool
  }
}

TEST(TimeOfImpact, AFaceFallingFlatOntoATessellatedFloor) {
  // Face on face: a box falls flat, or rocking by up to 1e-3 rad, onto a floor whose top is a
  // 16 x 16 grid, so that the 30-odd triangles under its face share one gap. The answer must be
  // the floor's as one convex slab (time_of_impact on the slab) to the tolerance's time, never
  // after the first contact (apart from the slab at 50 sampled times before it), within the
  // tolerance at it; and the triangles under the face that cannot touch the box before the
  // first hit are not advanced: a few times the slab's iterations, not one slab's per tie.
  const tools::Mesh floor = tools::box_mesh(Vector3d(-1, -1, -0.1), Vector3d(1, 1, 0), 16);
  Octree mesh;
  ASSERT_EQ(build_octree(floor.vertices, floor.triangles, mesh), Status::Ok);
  ConvexShape slab, tool;
  ASSERT_EQ(shape_from_box(Box{Vector3d(0, 0, -0.05), Eigen::Matrix3d::Identity(), Vector3d(1, 1, 0.05)}, slab),
            Status::Ok);
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(0.3, 0.2, 0.1)}, tool),
            Status::Ok);
  std::mt19937_64 rng(71);
  std::uniform_real_distribution<double> unit(-1, 1);
  long mesh_iterations = 0, slab_iterations = 0;
  const int sweeps = test::scaled(40);
  for (int k = 0; k < sweeps; ++k) {
    // Flat and translating; tilted and translating; rocking through flat (turning).
    const double tilt0 = k % 3 == 0 ? 0.0 : 1e-3 * unit(rng), tilt1 = k % 3 == 2 ? -tilt0 : tilt0;
    const double yaw = 3 * unit(rng);
    const Vector3d from(0.4 * unit(rng), 0.4 * unit(rng), 0.4), to = from + Vector3d(0.2 * unit(rng), 0.2 * unit(rng), -0.6);
    const Isometry3d t0 = Eigen::Translation3d(from) * Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) *
                          Eigen::AngleAxisd(tilt0, Vector3d::UnitX());
    const Isometry3d t1 = Eigen::Translation3d(to) * Eigen::AngleAxisd(yaw, Vector3d::UnitZ()) *
                          Eigen::AngleAxisd(tilt1, Vector3d::UnitX());
    const double tolerance = k % 3 == 2 ? 1e-7 : 1e-11;
    const std::string where = "sweep " + std::to_string(k);
    TimeOfImpact toi, one;
    ASSERT_EQ(time_of_impact(mesh, kIdentity, tool, t0, t1, toi, tolerance), Status::Ok) << where;
    ASSERT_EQ(time_of_impact(slab, kIdentity, kIdentity, tool, t0, t1, one, tolerance), Status::Ok) << where;
    ASSERT_TRUE(toi.hit && toi.converged && one.hit) << where;
    EXPECT_NEAR(toi.time, one.time, 1e-6) << where;
    EXPECT_LE(oracle(slab, kIdentity, tool, at(t0, t1, toi.time)).distance, tolerance * (1 + 1e-6)) << where;
    for (int s = 0; s < 50; ++s)
      ASSERT_FALSE(oracle(slab, kIdentity, tool, at(t0, t1, toi.time * s / 50)).overlap) << where << " sample " << s;
    mesh_iterations += toi.iterations, slab_iterations += one.iterations;
  }
  // (Each tie advanced would cost about the slab's iterations: 30-odd times as many.)
  EXPECT_LE(mesh_iterations, 4 * slab_iterations);
}

TEST(TimeOfImpact, BadInputAndOverlapAtTheStart) {
  ConvexShape A, B, empty;
  ASSERT_EQ(shape_from_box(Box{}, A), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, B), Status::Ok);
  const Isometry3d far(Eigen::Translation3d(0, 0, 5)), near(Eigen::Translation3d(0, 0, 1.5));
  TimeOfImpact toi;
  // Overlapping already (pose0 = pose1 too): time 0.
  ASSERT_EQ(time_of_impact(A, kIdentity, kIdentity, B, near, near, toi), Status::Ok);
  EXPECT_TRUE(toi.hit);
  EXPECT_EQ(toi.time, 0);
  // Apart and still: no hit.
  ASSERT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, far, toi), Status::Ok);
  EXPECT_FALSE(toi.hit);
  EXPECT_EQ(toi.time, 1);
  // Moving apart: no hit; moving in: faces 3 apart close at 4 per tick, touching at 3/4.
  ASSERT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, Isometry3d(Eigen::Translation3d(0, 0, 9)), toi),
            Status::Ok);
  EXPECT_FALSE(toi.hit);
  ASSERT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, Isometry3d(Eigen::Translation3d(0, 0, 1)), toi),
            Status::Ok);
  EXPECT_TRUE(toi.hit);
  EXPECT_LE(toi.time, 0.75);
  EXPECT_GE(toi.time, 0.75 - toi.tolerance / 4);
  EXPECT_NEAR(toi.normal.z(), 1, 1e-12);
  EXPECT_NEAR(toi.point_a.z(), 1, 1e-12);
  // Bad input: a status, and the answer reset.
  Isometry3d nan = far;
  nan(0, 3) = std::nan("");
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, nan, toi), Status::InvalidPose);
  EXPECT_FALSE(toi.hit);
  Isometry3d scaled = far;
  scaled.linear() *= 1.01;
  EXPECT_EQ(time_of_impact(A, scaled, kIdentity, B, far, far, toi), Status::InvalidPose);
  // One object as both poses of a still shape (a batch's, whose start and end are one array):
  // checked all the same (it was skipped as "the end pose, checked as the start").
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, scaled, scaled, toi), Status::InvalidPose);
  EXPECT_EQ(time_of_impact(A, scaled, scaled, B, far, far, toi), Status::InvalidPose);
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, far, toi, -1), Status::InvalidArgument);
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, far, toi, std::nan("")), Status::InvalidArgument);
  EXPECT_EQ(time_of_impact(empty, kIdentity, kIdentity, B, far, far, toi), Status::TooFewPoints);
  // Against a mesh: the same statuses.
  Octree mesh, none;
  ASSERT_EQ(build_octree(A.polytope().vertices, {{0, 1, 2}}, mesh), Status::Ok);
  EXPECT_EQ(time_of_impact(mesh, kIdentity, B, far, nan, toi), Status::InvalidPose);
  EXPECT_EQ(time_of_impact(mesh, scaled, B, far, far, toi), Status::InvalidPose);
  EXPECT_EQ(time_of_impact(mesh, kIdentity, B, far, far, toi, -1), Status::InvalidArgument);
  EXPECT_EQ(time_of_impact(mesh, kIdentity, empty, far, far, toi), Status::TooFewPoints);
  EXPECT_EQ(time_of_impact(none, kIdentity, B, far, far, toi), Status::TooFewPoints);
}


// The distance from x to the box [-1, 1]^3, in closed form (the band's oracle: not the library).
double box_distance(const Vector3d& x) { return (x.cwiseAbs() - Vector3d::Ones()).cwiseMax(0.0).norm(); }

// The least of box_distance along p0 + t (p1 - p0) over t in [lo, hi]: convex in t, so a
// ternary search finds it.
double least_distance(const Vector3d& p0, const Vector3d& p1, double lo, double hi) {
  const auto f = [&](double t) { return box_distance(p0 + t * (p1 - p0)); };
  for (int k = 0; k < 200 && hi - lo > 1e-15; ++k) {
    const double a = lo + (hi - lo) / 3, b = hi - (hi - lo) / 3;
    (f(a) < f(b) ? hi : lo) = f(a) < f(b) ? b : a;
  }
  return std::min({f(lo), f(hi), f(0.5 * (lo + hi))});
}

// The band's contract (TimeOfImpact): a pass closer than tolerance / 2 always hits, no later
// than its first such moment; no hit while farther than the tolerance. Grazing translations of
// a 1e-9 tetrahedron past the box [-1, 1]^3 by a face, an edge or a corner, each passing at
// 0.05 ... 2 tolerances (the closest approach from the closed form above), through the convex
// sweep and the box as a mesh. Broken before: a convex step closed gaps within the tolerance to
// 0, stepping over passes at 0.5-0.9 of it (216 of 268 missed at 0.9).
TEST(TimeOfImpact, TheBandHasOneContractConvexAndMesh) {
  const double tol = 1e-3, size = 1e-9;
  ConvexShape A, B;
  ASSERT_EQ(shape_from_box(Box{}, A), Status::Ok);
  ASSERT_EQ(shape_from_points({Vector3d::Zero(), Vector3d(size, 0, 0), Vector3d(0, size, 0), Vector3d(0, 0, size)}, B),
            Status::Ok);
  const tools::Mesh box = tools::box_mesh(-Vector3d::Ones(), Vector3d::Ones(), 4);
  Octree mesh;
  ASSERT_EQ(build_octree(box.vertices, box.triangles, mesh), Status::Ok);
  std::mt19937 rng(53);
  std::uniform_real_distribution<double> u(-1, 1);
  const double fractions[] = {0.05, 0.2, 0.45, 0.55, 0.9, 1.1, 2};
  int hits_below = 0, misses_above = 0, checked = 0;
  for (int k = 0; k < 600; ++k) {
    const double c = fractions[k % 7];
    // The closest point's region: a face (0), an edge (1) or a corner (2) of the box, its
    // outward offset w (unit), and a motion square to w through the closest point.
    const int region = k / 7 % 3;
    Vector3d on(0.8 * u(rng), 0.8 * u(rng), 1), w = Vector3d::UnitZ();
    if (region == 1) on.x() = 1, w = Vector3d(1 + u(rng), 0, 1 + u(rng)).normalized();
    if (region == 2) on = Vector3d::Ones(), w = Vector3d(1.2 + u(rng), 1.2 + u(rng), 1.2 + u(rng)).normalized();
    const Vector3d x = on + c * tol * w, d = w.cross(Vector3d(u(rng), u(rng), u(rng))).normalized() * 0.3;
    const double t_star = 0.2 + 0.6 * (u(rng) + 1) / 2;  // where the motion passes x
    Isometry3d p0 = kIdentity, p1 = kIdentity;
    p0.translation() = x - t_star * d, p1.translation() = x + (1 - t_star) * d;
    const double least = least_distance(p0.translation(), p1.translation(), 0, 1);
    for (int kind = 0; kind < 2; ++kind) {
      TimeOfImpact toi;
      const Status s = kind == 0 ? time_of_impact(A, kIdentity, kIdentity, B, p0, p1, toi, tol)
                                 : time_of_impact(mesh, kIdentity, B, p0, p1, toi, tol);
      ASSERT_EQ(s, Status::Ok);
      ASSERT_TRUE(toi.converged) << k;
      ++checked;
      const char* what = kind == 0 ? "convex" : "mesh";
      if (least < 0.5 * tol - 2 * size) {
        EXPECT_TRUE(toi.hit) << what << " pass " << k << " at " << least / tol << " of the tolerance: no hit";
        hits_below += toi.hit;
      }
      if (least > tol + 2 * size) {
        EXPECT_FALSE(toi.hit) << what << " pass " << k << " at " << least / tol << " of the tolerance: a hit";
        misses_above += !toi.hit;
      }
      if (!toi.hit) continue;
      const Vector3d at_hit = p0.translation() + toi.time * (p1.translation() - p0.translation());
      EXPECT_LE(box_distance(at_hit), tol + 2 * size) << what << " pass " << k << ": a hit farther than the tolerance";
      EXPECT_LE(toi.distance, tol) << what << " pass " << k;
      if (toi.time > 0)
        EXPECT_GE(least_distance(p0.translation(), p1.translation(), 0, toi.time), 0.5 * tol - 2 * size)
            << what << " pass " << k << ": a pass within half the tolerance before the hit";
    }
  }
  EXPECT_EQ(checked, 1200);
  EXPECT_GT(hits_below, 600 / 7 * 3 * 2 - 10);  // the passes below half the tolerance, both kinds
  EXPECT_GT(misses_above, 600 / 7 * 2 * 2 - 10);
}


// Whether B, moving with at most `speed` per unit time (|v| + angle r over the tick), stays at
// least `floor` from A at every time of [lo, hi], given the brute-force distances at its ends
// (test::brute_force: not the library): d is Lipschitz with that speed, so an interval whose
// ends are far enough apart proves itself, and the others are halved. An interval that cannot
// be proven down to 1e-12 of the tick stands if its middle is at least the floor less 1e-5 of
// it (rounding). False where the distance dips below: a pass the contract says must hit.
bool stays_apart(const ConvexShape& A, const ConvexShape& B, const Isometry3d& b0, const Isometry3d& b1, double lo,
                 double hi, double dlo, double dhi, double speed, double floor, int depth = 0) {
  if (dlo + dhi - speed * (hi - lo) >= 2 * floor) return true;
  const double mid = 0.5 * (lo + hi);
  const test::Oracle o = oracle(A, kIdentity, B, at(b0, b1, mid));
  const double dmid = o.overlap ? 0.0 : o.distance;
  if (dmid < floor * (1 - 1e-5)) return false;
  if (hi - lo < 1e-12 || depth > 60) return true;
  return stays_apart(A, B, b0, b1, lo, mid, dlo, dmid, speed, floor, depth + 1) &&
         stays_apart(A, B, b0, b1, mid, hi, dmid, dhi, speed, floor, depth + 1);
}

// Bodies that turn about a point far from their centre (a lever arm of 10 to 100 times their
// size) swing past A: a wrong rotational bound (one taken about the centre, or missing the
// arm) steps over the pass. Against brute force with a Lipschitz bound between samples: no pass
// within half the tolerance before a hit (nor anywhere on a miss), and within the tolerance at
// the hit; the same against A's surface as a mesh.
TEST(TimeOfImpact, ALongLeverArmNeverStepsOverAPass) {
  std::mt19937_64 rng(10053);
  std::uniform_real_distribution<double> unit(-1, 1);
  ConvexShape A;
  ASSERT_EQ(shape_from_points(tools::sphere_points(14, 7), A), Status::Ok);
  std::vector<std::array<int, 3>> faces;
  for (const auto& f : A.polytope().faces)
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) faces.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
  Octree surface;
  ASSERT_EQ(build_octree(A.polytope().vertices, faces, surface), Status::Ok);
  int hits = 0, misses = 0;
  const int motions = test::scaled(60, 12);
  for (int k = 0; k < motions; ++k) {
    const double arm = k % 3 == 0 ? 5 : k % 3 == 1 ? 20 : 50;  // B is 0.5 across: 10 to 100 sizes
    std::vector<Vector3d> body = tools::scaled(tools::sphere_points(8 + k % 5, 300 + k), 0.25);
    for (auto& v : body) v.x() += arm;
    ConvexShape B;
    ASSERT_EQ(shape_from_points(body, B), Status::Ok);
    // B's origin about `arm` from A, its body swinging through A's neighbourhood by 0.2 rad,
    // offset across the swing by up to 1.5 (hits and misses).
    const double swing = 0.2, offset = 1.5 * unit(rng);
    const Isometry3d b0 = Eigen::Translation3d(-arm + offset, 0.3 * unit(rng), 0.8 * unit(rng)) *
                          Eigen::AngleAxisd(-swing / 2, Vector3d::UnitZ());
    const Isometry3d b1 = Eigen::Translation3d(b0.translation() + 0.05 * Vector3d(unit(rng), unit(rng), 0)) *
                          Eigen::AngleAxisd(swing / 2, Vector3d::UnitZ());
    double radius = 0;
    for (const auto& v : B.polytope().vertices) radius = std::max(radius, v.norm());
    const double speed = (b1.translation() - b0.translation()).norm() + swing * radius * (1 + 1e-9);
    const test::Oracle start = oracle(A, kIdentity, B, b0), end = oracle(A, kIdentity, B, b1);
    if (start.overlap) continue;
    for (int kind = 0; kind < 2; ++kind) {
      const std::string where = std::string(kind ? "mesh" : "convex") + " motion " + std::to_string(k);
      TimeOfImpact toi;
      ASSERT_EQ(kind == 0 ? time_of_impact(A, kIdentity, kIdentity, B, b0, b1, toi)
                          : time_of_impact(surface, kIdentity, B, b0, b1, toi, 1e-6 * (2 * arm + 2)),
                Status::Ok)
          << where;
      ASSERT_TRUE(toi.converged) << where;
      const double tol = toi.tolerance, until = toi.hit ? toi.time : 1.0;
      const test::Oracle last = toi.hit ? oracle(A, kIdentity, B, at(b0, b1, until)) : end;
      const double dlast = last.overlap ? 0.0 : last.distance;
      if (toi.hit) EXPECT_LE(dlast, tol * (1 + 1e-9)) << where << ": a hit farther than the tolerance";
      if (toi.hit && toi.time == 0) continue;
      EXPECT_TRUE(stays_apart(A, B, b0, b1, 0, until, start.distance, dlast, speed, 0.5 * tol))
          << where << (toi.hit ? ": a pass within half the tolerance before the hit" : ": a missed pass");
      (toi.hit ? hits : misses) += kind == 0;
    }
  }
  EXPECT_GT(hits, motions / 5);
  EXPECT_GT(misses, motions / 5);
}


// Ties (tests/ties.hpp): box pairs in exact contact, face on face, along an edge or at a corner,
// each quarter-turned, and box-triangle pairs likewise. B moves through its touching pose at the
// middle of the tick along a lattice direction that separates them at the start: the answer is
// a hit no later than 1/2, within the tolerance there, with no overlap before it (brute force);
// and the same against A as a mesh.
TEST(TimeOfImpact, TouchingTiesAreHitAtTheirContact) {
  std::mt19937_64 rng(5353);
  const int pairs = test::scaled(200, 40);
  int checked = 0;
  for (int k = 0; k < pairs; ++k) {
    ConvexShape A, B;
    test::ties::touching_shapes(rng, k % 2 == 0, A, B);
    ASSERT_FALSE(A.empty() || B.empty());
    // Away from A: from A's centroid towards B's, kept on the lattice (sums of lattice points
    // times counts, scaled by a power of two: every pose of the motion's middle is exact).
    Vector3d sa = Vector3d::Zero(), sb = Vector3d::Zero();
    for (const auto& v : A.polytope().vertices) sa += v;
    for (const auto& v : B.polytope().vertices) sb += v;
    const Vector3d dir = double(A.polytope().vertices.size()) * sb - double(B.polytope().vertices.size()) * sa;
    if (dir.isZero()) continue;
    int exponent = 0;
    std::frexp(dir.cwiseAbs().maxCoeff(), &exponent);
    const Vector3d away = std::ldexp(1.0, -exponent - 1) * dir;  // (largest component in [1/4, 1/2))
    const Isometry3d b0{Eigen::Translation3d(away)}, b1{Eigen::Translation3d(-away)};  // (the contact at 1/2)
    if (oracle(A, kIdentity, B, b0).overlap) continue;  // (a triangle lying in a face: no side to come from)
    std::vector<std::array<int, 3>> faces;
    for (const auto& f : A.polytope().faces)
      for (size_t c = 1; c + 1 < f.loop.size(); ++c) faces.push_back({f.loop[0], f.loop[c], f.loop[c + 1]});
    Octree surface;
    ASSERT_EQ(build_octree(A.polytope().vertices, faces, surface), Status::Ok);
    for (int kind = 0; kind < 2; ++kind) {
      const std::string where = std::string(kind ? "mesh" : "convex") + " pair " + std::to_string(k);
      TimeOfImpact toi;
      ASSERT_EQ(kind == 0 ? time_of_impact(A, kIdentity, kIdentity, B, b0, b1, toi)
                          : time_of_impact(surface, kIdentity, B, b0, b1, toi),
                Status::Ok)
          << where;
      ASSERT_TRUE(toi.converged) << where;
      ASSERT_TRUE(toi.hit) << where;
      EXPECT_LE(toi.time, 0.5) << where;
      const test::Oracle o = oracle(A, kIdentity, B, at(b0, b1, toi.time));
      EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << where;
      for (int s = 0; s < 50; ++s)
        EXPECT_FALSE(oracle(A, kIdentity, B, at(b0, b1, toi.time * s / 50)).overlap) << where << " sample " << s;
      ++checked;
    }
  }
  EXPECT_GT(checked, pairs);  // both kinds, on most pairs
}

}  // namespace
}  // namespace minksum
