// Time of impact (time_of_impact) against brute force (test::brute_force on the explicitly
// placed polytopes). Pure translation: the first contact by bisection on the overlap (the
// times of overlap of a translating pair are one interval), to which the answer must be equal
// to rounding and never after. With rotation: the shapes are apart at every one of 500
// sampled times before the answer, and within the tolerance at it; no hit means apart at every
// sampled time. A thin sheet swept by a small tool at 1, 3 and 10 m/s in a 1 ms tick, the tool
// clear of it at both ends: every sweep must hit.
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cmath>
#include <random>

#include "checks.hpp"
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
  // before the answer, within the tolerance at it, the normal a separating plane there; a
  // quarter turn about z (the box's bottom face on the top face at every time) is a pure
  // fall: the time is exact.
  ConvexShape A, box, octahedron;
  ASSERT_EQ(shape_from_box(Box{Vector3d(0, 0, -1), Eigen::Matrix3d::Identity(), Vector3d(3, 3, 1)}, A), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(1, 1, 1)}, box), Status::Ok);
  ASSERT_EQ(shape_from_points({{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}, octahedron),
            Status::Ok);
  const Vector3d axes[] = {Vector3d::UnitZ(), Vector3d::UnitX(), Vector3d(1, 1, 0).normalized(),
                           Vector3d(1, 0, 1).normalized(), Vector3d(1, 2, 2).normalized()};
  int hits = 0;
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
          for (int s = 0; s < 500; ++s)
            EXPECT_FALSE(oracle(A, kIdentity, *B, at(b0, b1, toi.time * s / 500)).overlap) << where;
          const Isometry3d pb = at(b0, b1, toi.time);
          const test::Oracle o = oracle(A, kIdentity, *B, pb);
          EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << where;
          const double g = gap_along(A, kIdentity, *B, pb, toi.normal);
          EXPECT_GE(g, -1e-12) << where;
          EXPECT_LE(g, toi.tolerance * (1 + 1e-9)) << where;
          if (B == &box && &axis == axes && angle == M_PI / 2) EXPECT_NEAR(toi.time, drop / (2.0 * drop), 1e-9);
          ++hits;
        }
  EXPECT_EQ(hits, 2 * 5 * 4 * 3);
}

TEST(TimeOfImpact, NoTunnellingThroughAThinSheet) {
  // A sheet 0.5 mm thick (20 cm wide) and a tool of 0.3 mm, in metres; in a 1 ms tick at 1, 3
  // and 10 m/s the tool moves 1, 3 and 10 mm, from about 0.1 mm above the sheet to below it
  // (clear of it at both ends), straight down or slanted, turning or not.
  ConvexShape sheet, tool;
  ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(0.1, 0.1, 0.25e-3)}, sheet),
            Status::Ok);
  ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(16, 7), 0.15e-3), tool), Status::Ok);
  int sweeps = 0;
  for (double speed : {1.0, 3.0, 10.0})
    for (int slant = 0; slant < 3; ++slant)
      for (bool turning : {false, true}) {
        const double step = speed * 1e-3;  // metres per tick
        const Vector3d down = Vector3d(0.2 * slant, 0.1 * slant, -1).normalized();
        const Vector3d start(0.01, -0.02, 0.25e-3 + 0.15e-3 + 0.1e-3);
        const Isometry3d t0 = Eigen::Translation3d(start) * Eigen::AngleAxisd(0.3, Vector3d::UnitX());
        const Isometry3d t1 = Eigen::Translation3d(start + step * down) *
                              Eigen::AngleAxisd(0.3 + (turning ? 2.0 : 0.0), Vector3d::UnitX());
        const std::string where =
            "speed " + std::to_string(speed) + " slant " + std::to_string(slant) + (turning ? " turning" : "");
        ASSERT_FALSE(oracle(sheet, kIdentity, tool, t0).overlap) << where;
        ASSERT_FALSE(oracle(sheet, kIdentity, tool, t1).overlap) << where << " (the tool must end clear)";
        TimeOfImpact toi;
        ASSERT_EQ(time_of_impact(sheet, kIdentity, kIdentity, tool, t0, t1, toi), Status::Ok) << where;
        EXPECT_TRUE(toi.hit) << where;
        EXPECT_TRUE(toi.converged) << where;
        // Translating, it first touches the sheet's top when its lowest point reaches it.
        double low = HUGE_VAL;
        for (const Vector3d& v : tool.polytope().vertices) low = std::min(low, (t0 * v).z());
        const double first = (low - 0.25e-3) / (-down.z() * step);
        if (!turning) EXPECT_NEAR(toi.time, first, 1e-9) << where;
        // Turning: apart before it, within the tolerance at it.
        for (int s = 0; s < 200; ++s)
          EXPECT_FALSE(oracle(sheet, kIdentity, tool, at(t0, t1, toi.time * s / 200)).overlap) << where;
        const test::Oracle o = oracle(sheet, kIdentity, tool, at(t0, t1, toi.time));
        EXPECT_LE(o.overlap ? 0.0 : o.distance, toi.tolerance * (1 + 1e-9)) << where;
        EXPECT_GT(toi.normal.z(), 0.9) << where;  // the sheet's top, towards the tool
        ++sweeps;
      }
  EXPECT_EQ(sweeps, 18);
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
  EXPECT_NEAR(toi.time, 0.75, 1e-12);
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
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, far, toi, -1), Status::InvalidArgument);
  EXPECT_EQ(time_of_impact(A, kIdentity, kIdentity, B, far, far, toi, std::nan("")), Status::InvalidArgument);
  EXPECT_EQ(time_of_impact(empty, kIdentity, kIdentity, B, far, far, toi), Status::TooFewPoints);
}

}  // namespace
}  // namespace minksum
