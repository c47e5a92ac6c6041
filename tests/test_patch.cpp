// Contact patches (contact_patch) against brute force: the supporting sets of the explicitly
// placed polytopes (every vertex within 1e-10 of the size of the extreme one along the normal),
// their convex hulls by gift wrapping, and their overlap as the hull of the vertices of each
// inside the other and the crossings of every edge pair; the patch must equal it within 1e-12
// of the size (both ways: every point of one lies within that of the other). The normal is
// checked on its own: the supports along it give the brute-force depth (or distance).
// Inputs: the face-to-face families (boxes, prisms, a box on a prism, an edge on a face;
// apart within the margin, touching, pressed; with and without rocking), the degenerate
// families on integer coordinates (every tie exact: faces on faces with coincident edges),
// and generic pairs (one-point patches).
#include <gtest/gtest.h>
#include <minksum/minksum.hpp>

#include <cmath>
#include <limits>
#include <random>

#include "checks.hpp"
#include "ties.hpp"
#include "support/shapes.hpp"

namespace minksum {
namespace {

using Eigen::Isometry3d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Points2 = std::vector<Vector2d>;

double cross(const Vector2d& a, const Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// The convex hull of pts by gift wrapping (Jarvis 1973), counter-clockwise, without collinear
// points: one point, two (a segment) or a polygon.
Points2 gift_wrap(const Points2& pts, double tol) {
  Points2 hull;
  if (pts.empty()) return hull;
  int start = 0;
  for (int k = 1; k < int(pts.size()); ++k)
    if (pts[k].x() < pts[start].x() || (pts[k].x() == pts[start].x() && pts[k].y() < pts[start].y())) start = k;
  int at = start;
  do {
    hull.push_back(pts[at]);
    int next = -1;
    for (int k = 0; k < int(pts.size()); ++k) {
      if ((pts[k] - pts[at]).norm() <= tol) continue;
      if (next < 0) {
        next = k;
        continue;
      }
      const double c = cross(pts[next] - pts[at], pts[k] - pts[at]);
      // k clockwise of next, or on its line and farther: the wrap turns to k.
      if (c < -tol * (pts[next] - pts[at]).norm() || (std::abs(c) <= tol * (pts[next] - pts[at]).norm() &&
                                                      (pts[k] - pts[at]).norm() > (pts[next] - pts[at]).norm()))
        next = k;
    }
    if (next < 0) break;  // every point within tol of one
    at = next;
  } while ((pts[at] - pts[start]).norm() > tol && hull.size() <= pts.size());
  return hull;
}

// Distance from x to the convex set h (a point, a segment or a counter-clockwise polygon).
double distance_to(const Points2& h, const Vector2d& x) {
  const int n = int(h.size());
  if (n >= 3) {
    bool inside = true;
    for (int k = 0; k < n; ++k) inside = inside && cross(h[(k + 1) % n] - h[k], x - h[k]) >= 0;
    if (inside) return 0;
  }
  double best = (x - h[0]).norm();
  for (int k = 0; k < n; ++k) {
    const Vector2d p = h[k], e = h[(k + 1) % n] - p;
    const double t = e.squaredNorm() > 0 ? std::clamp((x - p).dot(e) / e.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (p + t * e - x).norm());
  }
  return best;
}

// The overlap of two convex sets by brute force: the hull of the vertices of each within tol
// of the other and the crossing points of every edge pair.
Points2 overlap(const Points2& P, const Points2& Q, double tol) {
  Points2 pts;
  for (const auto& p : P)
    if (distance_to(Q, p) <= tol) pts.push_back(p);
  for (const auto& q : Q)
    if (distance_to(P, q) <= tol) pts.push_back(q);
  const auto edges = [](const Points2& h) {
    std::vector<std::pair<Vector2d, Vector2d>> e;
    for (int k = 0; k + 1 < int(h.size()) || (h.size() >= 3 && k < int(h.size())); ++k)
      e.push_back({h[k], h[(k + 1) % h.size()]});
    return e;
  };
  for (const auto& [a, b] : edges(P))
    for (const auto& [c, d] : edges(Q)) {
      const double den = cross(b - a, d - c);
      if (den == 0) continue;  // parallel: their ends inside the other cover the overlap
      const double s = cross(c - a, d - c) / den, t = cross(c - a, b - a) / den;
      if (s >= 0 && s <= 1 && t >= 0 && t <= 1) pts.push_back(a + s * (b - a));
    }
  return gift_wrap(pts, tol);
}

struct Placed {
  bool flat = false;  // one face, seen from either side (a triangle)
  std::vector<Vector3d> v;
  std::vector<Vector3d> face_normal;
  std::vector<std::vector<int>> face_loop;
};

Placed place(const ConvexShape& s, const Isometry3d& pose) {
  Placed p;
  p.flat = s.polytope().flat;
  for (const auto& x : s.polytope().vertices) p.v.push_back(pose * x);
  for (const auto& f : s.polytope().faces)
    p.face_normal.push_back(pose.linear() * f.normal), p.face_loop.push_back(f.loop);
  return p;
}

// Checks one patch against brute force; returns how many points it has.
int check_patch(const ConvexShape& A, const Isometry3d& pa, const ConvexShape& B, const Isometry3d& pb, double margin,
                const std::string& where) {
  ContactPatch patch;
  EXPECT_EQ(contact_patch(A, pa, B, pb, margin, patch), Status::Ok) << where;
  const Placed a = place(A, pa), b = place(B, pb);
  double size = 0;
  for (const auto* s : {&a, &b})
    for (const auto& x : s->v) size = std::max(size, x.cwiseAbs().maxCoeff());
  const double tol = 1e-12 * std::max(1.0, size);
  const test::Oracle o = test::brute_force(test::transformed(A.polytope(), pa), test::transformed(B.polytope(), pb));
  EXPECT_NEAR(patch.depth, o.overlap ? o.depth : -o.distance, tol) << where;
  if (!o.overlap && o.distance > margin + tol) {
    EXPECT_EQ(patch.size, 0) << where;
    return 0;
  }
  if (o.overlap || o.distance < margin - tol) EXPECT_GT(patch.size, 0) << where;
  if (patch.size == 0) return 0;
  const Vector3d n = patch.normal;
  EXPECT_NEAR(n.norm(), 1.0, 1e-12) << where;
  // The normal: the supports along it give the depth (overlapping) or the distance (apart).
  double top = -HUGE_VAL, bottom = HUGE_VAL;
  for (const auto& x : a.v) top = std::max(top, n.dot(x));
  for (const auto& x : b.v) bottom = std::min(bottom, n.dot(x));
  EXPECT_NEAR(top - bottom, patch.depth, tol) << where;
  // The supporting sets, their hulls and overlap seen along n, in a basis of the test's own.
  const int axis = n.cwiseAbs().minCoeff() == std::abs(n.x()) ? 0 : n.cwiseAbs().minCoeff() == std::abs(n.y()) ? 1 : 2;
  const Vector3d u = n.cross(Vector3d::Unit(axis)).normalized(), w = n.cross(u);
  const auto set = [&](const Placed& s, double level, double sign, std::vector<int>& which) {
    Points2 pts;
    for (int k = 0; k < int(s.v.size()); ++k)
      if (sign * (n.dot(s.v[k]) - level) >= -1e-10 * std::max(1.0, size))
        pts.push_back({u.dot(s.v[k]), w.dot(s.v[k])}), which.push_back(k);
    return gift_wrap(pts, tol);
  };
  std::vector<int> in_a, in_b;
  const Points2 expected = overlap(set(a, top, 1, in_a), set(b, bottom, -1, in_b), tol);
  Points2 got;
  for (int k = 0; k < patch.size; ++k) {
    EXPECT_NEAR(n.dot(patch.points[k]), top, tol) << where << " point " << k;
    got.push_back({u.dot(patch.points[k]), w.dot(patch.points[k])});
  }
  EXPECT_FALSE(expected.empty()) << where;
  if (expected.empty()) return patch.size;
  for (const auto& x : got) EXPECT_LE(distance_to(expected, x), tol) << where;
  for (const auto& x : expected) EXPECT_LE(distance_to(got, x), tol) << where << " (a point the patch misses)";
  // Counter-clockwise about n, and convex.
  for (int k = 0; patch.size >= 3 && k < patch.size; ++k)
    EXPECT_GT(cross(got[(k + 1) % patch.size] - got[k], got[(k + 2) % patch.size] - got[(k + 1) % patch.size]), 0)
        << where << " corner " << k;
  // The features: their vertices are in the supporting sets; a face faces along n (A) or -n (B).
  const auto feature = [&](const ContactPatch::Feature& f, const Placed& s, double sign, const std::vector<int>& in) {
    using Kind = ContactPatch::Feature::Kind;
    const auto holds = [&](int v) { return std::find(in.begin(), in.end(), v) != in.end(); };
    if (f.kind == Kind::Face) {
      ASSERT_TRUE(f.index[0] >= 0 && f.index[0] < int(s.face_loop.size())) << where;
      const double along = s.face_normal[f.index[0]].dot(n);
      EXPECT_GT(s.flat ? std::abs(along) : sign * along, 1 - 1e-9) << where;
      for (int v : s.face_loop[f.index[0]]) EXPECT_TRUE(holds(v)) << where;
    } else if (f.kind == Kind::Edge || f.kind == Kind::Vertex) {
      EXPECT_TRUE(holds(f.index[0])) << where;
      if (f.kind == Kind::Edge) EXPECT_TRUE(holds(f.index[1])) << where;
    }
  };
  feature(patch.feature_a, a, 1, in_a);
  feature(patch.feature_b, b, -1, in_b);
  return patch.size;
}

const Isometry3d kPoseA(Eigen::Translation3d(0.3, -0.2, 0.1) * Eigen::AngleAxisd(0.4, Vector3d(1, 2, 3).normalized()));

TEST(ContactPatch, FaceFamiliesEqualBruteForce) {
  const int stride = 30 / std::min(10, test::scaled(10));  // every 3rd of 64 ticks
  int polygons = 0, segments = 0, points = 0, checked = 0;
  for (const auto& pair : tools::face_pairs()) {
    ConvexShape A, B;
    ASSERT_EQ(pair.a_is_box ? shape_from_box(pair.box_a, A) : shape_from_points(pair.a, A), Status::Ok);
    ASSERT_EQ(pair.b_is_box ? shape_from_box(pair.box_b, B) : shape_from_points(pair.b, B), Status::Ok);
    for (bool rocking : {false, true})
      for (double gap : {1e-3, 1e-9, 0.0, -1e-9, -1e-3})
        for (int k = 0; k < 64; k += stride) {
          const Isometry3d pose_b = kPoseA * tools::face_pose(pair, k, 64, gap, rocking);
          const int n = check_patch(
              A, kPoseA, B, pose_b, 2e-3,
              pair.name + (rocking ? " rocking" : "") + " gap " + std::to_string(gap) + " tick " + std::to_string(k));
          polygons += n >= 3, segments += n == 2, points += n == 1, ++checked;
        }
  }
  // Sliding flat, the patches are polygons (and segments: an edge along a face); rocking, B's
  // tilted face meets A's at a corner, or along an edge.
  EXPECT_GT(polygons, checked / 3);
  EXPECT_GT(segments, checked / 10);
  EXPECT_GT(points, checked / 10);
}

TEST(ContactPatch, IntegerFamiliesWithExactTiesEqualBruteForce) {
  // The degenerate families on integer coordinates, B moved by integer steps onto, into and
  // beside A (faces on faces with coincident edges and corners): every tie exact.
  std::mt19937_64 rng(23);
  std::uniform_int_distribution<int> step(-3, 3);
  int polygons = 0;
  for (int family = 0; family < tools::kDegenerateFamilies; ++family)
    for (int round = 0; round < test::scaled(12); ++round) {
      const tools::DegeneratePair p = tools::degenerate_pair(family, rng);
      ConvexShape A, B;
      ASSERT_EQ(shape_from_points(p.a, A), Status::Ok);
      ASSERT_EQ(shape_from_points(p.b, B), Status::Ok);
      double top = -HUGE_VAL, bottom = HUGE_VAL;
      for (const auto& x : p.a) top = std::max(top, x.z());
      for (const auto& x : p.b) bottom = std::min(bottom, x.z());
      for (int lift : {0, -1, 1}) {  // B's bottom on A's top, pressed one unit, apart one unit
        const Isometry3d pose_b(Eigen::Translation3d(step(rng), step(rng), top - bottom + lift));
        const int n = check_patch(A, Isometry3d::Identity(), B, pose_b, 1.5,
                                  p.name + " round " + std::to_string(round) + " lift " + std::to_string(lift));
        polygons += n >= 3;
      }
    }
  EXPECT_GT(polygons, 0);
}

TEST(ContactPatch, GenericPairsAreOnePoint) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> coord(-0.8, 0.8);
  int points = 0;
  const int pairs = test::scaled(400);
  for (int k = 0; k < pairs; ++k) {
    ConvexShape A, B;
    ASSERT_EQ(shape_from_points(tools::sphere_points(20, 100 + k), A), Status::Ok);
    ASSERT_EQ(shape_from_points(tools::scaled(tools::sphere_points(12, 7000 + k), 0.7), B), Status::Ok);
    const Isometry3d pa(Eigen::AngleAxisd(coord(rng), Vector3d(1, 0, 0)));
    const Isometry3d pb(Eigen::Translation3d(coord(rng), coord(rng), coord(rng) + 1.2) *
                        Eigen::AngleAxisd(coord(rng), Vector3d(0, 1, 1).normalized()));
    points += check_patch(A, pa, B, pb, 0.5, "generic " + std::to_string(k)) == 1;
  }
  EXPECT_GT(points, pairs / 2);  // a vertex on a face, or an edge across an edge
}

// Box shapes take their own path (the 15 separating axes, see contact_patch); it must equal
// brute force on every kind of contact, and hand over where the axes do not decide: boxes in
// random poses (corners on faces, edges across edges, corners on corners apart within the
// margin), aligned boxes on integer coordinates (coincident faces, edges and corners: exact
// ties), and boxes turned by 1e-7 to 1e-4 rad from face on face (axes nearly parallel).
TEST(ContactPatch, BoxPairsEqualBruteForce) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> unit(-1, 1), size(0.1, 1.0);
  const auto rotation = [&] { return Eigen::Quaterniond::UnitRandom().toRotationMatrix(); };
  const auto place = [&](const Box& box, ConvexShape& s) { ASSERT_EQ(shape_from_box(box, s), Status::Ok); };
  int polygons = 0, segments = 0, points = 0;
  const int rounds = test::scaled(300);
  {  // An edge resting on a face (B turned 45 degrees about x onto A's top): a segment, whatever
     // the random draws give (their order is the compiler's: clang and GCC draw other boxes).
    ConvexShape A, B;
    place(Box{}, A);
    place(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d::Constant(0.5)}, B);
    const Isometry3d pb(Eigen::Translation3d(0.25, 0, 1 + 0.5 * std::sqrt(2.0)) *
                        Eigen::AngleAxisd(M_PI / 4, Vector3d::UnitX()));
    const int n = check_patch(A, Isometry3d::Identity(), B, pb, 0.5, "edge on face");
    EXPECT_EQ(n, 2);
    segments += n == 2;
  }
  for (int k = 0; k < rounds; ++k) {
    ConvexShape A, B;
    // Random: B's centre placed at a random distance from A's along a random direction.
    std::srand(unsigned(rng()));  // (Eigen's UnitRandom draws from rand())
    place(Box{Vector3d(unit(rng), unit(rng), unit(rng)), rotation(), Vector3d(size(rng), size(rng), size(rng))}, A);
    place(Box{Vector3d::Zero(), rotation(), Vector3d(size(rng), size(rng), size(rng))}, B);
    const Isometry3d pa(Eigen::Translation3d(0.1, 0.2, -0.3) * Eigen::Quaterniond::UnitRandom());
    const Isometry3d pb(Eigen::Translation3d(2.0 * Vector3d(unit(rng), unit(rng), unit(rng))) *
                        Eigen::Quaterniond::UnitRandom());
    const int n = check_patch(A, pa, B, pb, 0.5, "random boxes " + std::to_string(k));
    polygons += n >= 3, segments += n == 2, points += n == 1;
  }
  std::uniform_int_distribution<int> half(1, 3), step(-4, 4), quarter(0, 3);
  for (int k = 0; k < rounds; ++k) {
    // Aligned on integers, B turned by quarter turns: every tie exact.
    ConvexShape A, B;
    place(Box{Vector3d(step(rng), step(rng), 0), Eigen::Matrix3d::Identity(), Vector3d(half(rng), half(rng), 1)}, A);
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(M_PI / 2 * quarter(rng), Vector3d::UnitZ()).toRotationMatrix().unaryExpr([](double x) {
          return std::round(x);
        });
    place(Box{Vector3d::Zero(), turn, Vector3d(half(rng), half(rng), half(rng))}, B);
    const Isometry3d pb(Eigen::Translation3d(step(rng), step(rng), step(rng)));
    const int n = check_patch(A, Isometry3d::Identity(), B, pb, 1.5, "integer boxes " + std::to_string(k));
    polygons += n >= 3, segments += n == 2, points += n == 1;
  }
  for (int k = 0; k < rounds; ++k) {
    // Face on face, B turned by 10^-e rad about a random axis (touching, pressed or apart).
    ConvexShape A, B;
    place(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(1, 0.7, 0.5)}, A);
    place(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(0.4, 0.3, 0.2)}, B);
    // (An axis that tilts every corner of B's face by 0.1 angle or more from the others:
    // smaller height differences would sit between the brute force's 1e-10 and rounding.)
    const double angle = std::pow(10.0, -4 - k % 4);
    const auto either = [&](double lo, double hi) { return (unit(rng) < 0 ? -1 : 1) * (lo + (hi - lo) * size(rng)); };
    const Vector3d axis = Vector3d(either(0.8, 1), either(0.2, 0.4), unit(rng)).normalized();
    const Isometry3d pb(Eigen::Translation3d(0.3 * unit(rng), 0.3 * unit(rng), 0.7 + 1e-3 * (k % 3 - 1)) *
                        Eigen::AngleAxisd(angle, axis));
    const int n = check_patch(A, kPoseA, B, kPoseA * pb, 2e-3, "turned 1e-" + std::to_string(4 + k % 4));
    polygons += n >= 3, segments += n == 2, points += n == 1;
  }
  EXPECT_GT(polygons, rounds / 4);
  EXPECT_GT(segments, 0);
  EXPECT_GT(points, rounds / 4);
}

// A box and a triangle take their own path (13 separating axes), either way round: random
// poses, and integer triangles on, into and beside an integer box (corners and edges on its
// faces and edges: exact ties).
TEST(ContactPatch, BoxTrianglePairsEqualBruteForce) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> unit(-1, 1), size(0.2, 1.0);
  std::uniform_int_distribution<int> step(-3, 3);
  int polygons = 0, segments = 0, points = 0;
  const int rounds = test::scaled(200);
  for (int k = 0; k < 2 * rounds; ++k) {
    std::srand(unsigned(rng()));  // (Eigen's UnitRandom draws from rand())
    ConvexShape box, tri;
    Triangle t;
    Isometry3d pose_box = Isometry3d::Identity(), pose_tri = Isometry3d::Identity();
    if (k < rounds) {
      ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Quaterniond::UnitRandom().toRotationMatrix(),
                                   Vector3d(size(rng), size(rng), size(rng))},
                               box),
                Status::Ok);
      t = Triangle{Vector3d(unit(rng), unit(rng), unit(rng)), Vector3d(unit(rng), unit(rng), unit(rng)),
                   Vector3d(unit(rng), unit(rng), unit(rng))};
      pose_box = Isometry3d(Eigen::Translation3d(0.2 * Vector3d(unit(rng), unit(rng), unit(rng))) *
                            Eigen::Quaterniond::UnitRandom());
      pose_tri = Isometry3d(Eigen::Translation3d(1.2 * Vector3d(unit(rng), unit(rng), unit(rng))));
    } else {
      ASSERT_EQ(shape_from_box(Box{Vector3d::Zero(), Eigen::Matrix3d::Identity(), Vector3d(2, 2, 1)}, box), Status::Ok);
      const auto corner = [&] { return Vector3d(step(rng), step(rng), 1 + (k % 3 == 0 ? step(rng) % 2 : 0)); };
      t = Triangle{corner(), corner(), corner()};
      pose_tri = Isometry3d(Eigen::Translation3d(0, 0, k % 3 - 1));
    }
    if (shape_from_triangle(t, tri) != Status::Ok) continue;  // (collinear integer corners)
    const std::string where = "box-triangle " + std::to_string(k);
    for (bool box_first : {true, false}) {
      const int n = box_first ? check_patch(box, pose_box, tri, pose_tri, 0.5, where)
                              : check_patch(tri, pose_tri, box, pose_box, 0.5, where + " (swapped)");
      polygons += n >= 3, segments += n == 2, points += n == 1;
    }
  }
  EXPECT_GT(polygons, 0);
  EXPECT_GT(segments, 0);
  EXPECT_GT(points, rounds / 2);
}

// The coherent patch (through a ProximityCache) along the face-to-face slides equals the cold
// one: the same size and features, normal and depth to 1e-12, and every point within 1e-12 of
// the other's set; and the cache answers warm on most of the clear (apart or pressed) ticks.
TEST(ContactPatch, CoherentEqualsCold) {
  long warm = 0, clear = 0;
  for (const auto& pair : tools::face_pairs()) {
    ConvexShape A, B;
    ASSERT_EQ(pair.a_is_box ? shape_from_box(pair.box_a, A) : shape_from_points(pair.a, A), Status::Ok);
    ASSERT_EQ(pair.b_is_box ? shape_from_box(pair.box_b, B) : shape_from_points(pair.b, B), Status::Ok);
    for (bool rocking : {false, true})
      for (double gap : {1e-3, 0.0, -1e-3}) {
        ProximityCache cache;
        for (int k = 0; k < 64; ++k) {
          const Isometry3d pose_b = kPoseA * tools::face_pose(pair, k, 64, gap, rocking);
          const std::string where =
              pair.name + (rocking ? " rocking" : "") + " gap " + std::to_string(gap) + " tick " + std::to_string(k);
          ContactPatch cold, coherent;
          ASSERT_EQ(contact_patch(A, kPoseA, B, pose_b, 2e-3, cold), Status::Ok) << where;
          const long before = cache.warm;
          ASSERT_EQ(contact_patch(A, kPoseA, B, pose_b, 2e-3, cache, coherent), Status::Ok) << where;
          warm += cache.warm - before, clear += gap != 0;
          ASSERT_EQ(coherent.size, cold.size) << where;
          EXPECT_NEAR((coherent.normal - cold.normal).norm(), 0, 1e-12) << where;
          EXPECT_NEAR(coherent.depth, cold.depth, 1e-12) << where;
          EXPECT_EQ(coherent.feature_a.kind, cold.feature_a.kind) << where;
          EXPECT_EQ(coherent.feature_b.kind, cold.feature_b.kind) << where;
          const Vector3d u = cold.normal.unitOrthogonal(), w = cold.normal.cross(u);
          Points2 x, y;
          for (int j = 0; j < cold.size; ++j) x.push_back({u.dot(cold.points[j]), w.dot(cold.points[j])});
          for (int j = 0; j < coherent.size; ++j) y.push_back({u.dot(coherent.points[j]), w.dot(coherent.points[j])});
          for (const auto& q : x) EXPECT_LE(distance_to(y, q), 1e-12) << where;
          for (const auto& q : y) EXPECT_LE(distance_to(x, q), 1e-12) << where;
        }
      }
  }
  EXPECT_GT(warm, clear / 2);
}

// The largest area of a quadrilateral on the points of a convex polygon, by trying every four.
double largest_quadrilateral(const std::vector<Vector3d>& p, const Vector3d& n) {
  const auto area = [&](int i, int j, int k) { return (p[j] - p[i]).cross(p[k] - p[i]).dot(n); };
  double best = 0;
  const int m = int(p.size());
  for (int i = 0; i < m; ++i)
    for (int j = i + 1; j < m; ++j)
      for (int k = j + 1; k < m; ++k)
        for (int l = k + 1; l < m; ++l) best = std::max(best, area(i, j, k) + area(i, k, l));
  return best;
}

// reduce_contact_patch keeps 4 of the patch's points, counter-clockwise, whose quadrilateral
// has the largest area (by brute force): random convex polygons, regular ones (every chord
// has parallel twins: ties), hulls of integer points, and polygons with points along their
// edges (collinear triples).
TEST(ContactPatch, ReductionKeepsTheLargestQuadrilateral) {
  std::mt19937_64 rng(37);
  std::uniform_real_distribution<double> unit(0, 1);
  std::uniform_int_distribution<int> grid(-5, 5);
  int reduced = 0;
  for (int round = 0; round < test::scaled(240); ++round) {
    // A plane in space: the polygon's points in its basis (u, w), counter-clockwise about n.
    const Eigen::Matrix3d frame = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    const Vector3d u = frame.col(0), w = frame.col(1), n = frame.col(2), o(unit(rng), unit(rng), unit(rng));
    Points2 flat;
    const int kind = round % 4, count = 5 + round % 36;
    if (kind == 0) {  // random angles on an ellipse
      std::vector<double> t;
      for (int k = 0; k < count; ++k) t.push_back(2 * M_PI * unit(rng));
      std::sort(t.begin(), t.end());
      for (double a : t) flat.push_back({2 * std::cos(a), 0.7 * std::sin(a)});
    } else if (kind == 1) {  // regular
      for (int k = 0; k < count; ++k) flat.push_back({std::cos(2 * M_PI * k / count), std::sin(2 * M_PI * k / count)});
    } else if (kind == 2) {  // the hull of integer points
      Points2 pts;
      for (int k = 0; k < count; ++k) pts.push_back({double(grid(rng)), double(grid(rng))});
      flat = gift_wrap(pts, 1e-12);
    } else {  // a rectangle with points along its sides
      const int along = 1 + round % 5;
      const Vector2d c[4] = {{0, 0}, {3, 0}, {3, 2}, {0, 2}};
      for (int s = 0; s < 4; ++s)
        for (int k = 0; k < along; ++k) flat.push_back(c[s] + (c[(s + 1) % 4] - c[s]) * double(k) / along);
    }
    ContactPatch patch;
    patch.normal = n, patch.size = int(flat.size());
    std::vector<Vector3d> original;
    for (int k = 0; k < patch.size; ++k) patch.points[k] = o + flat[k].x() * u + flat[k].y() * w;
    original.assign(patch.points, patch.points + patch.size);
    reduce_contact_patch(patch);
    const std::string where = "round " + std::to_string(round) + " kind " + std::to_string(kind);
    if (original.size() <= 4) {
      EXPECT_EQ(patch.size, int(original.size())) << where;
      continue;
    }
    ++reduced;
    ASSERT_EQ(patch.size, 4) << where;
    for (int k = 0; k < 4; ++k)
      EXPECT_NE(std::find(original.begin(), original.end(), patch.points[k]), original.end()) << where;
    double got = 0;
    for (int k = 1; k + 1 < 4; ++k) {
      const double a = (patch.points[k] - patch.points[0]).cross(patch.points[k + 1] - patch.points[0]).dot(n);
      EXPECT_GT(a, 0) << where << " (not counter-clockwise)";
      got += a;
    }
    EXPECT_NEAR(got, largest_quadrilateral(original, n), 1e-12 * (1 + got)) << where;
  }
  EXPECT_GT(reduced, test::scaled(240) / 2);
}

TEST(ContactPatch, MarginAndBadInput) {
  ConvexShape A, B, empty;
  ASSERT_EQ(shape_from_box(Box{}, A), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, B), Status::Ok);
  const Isometry3d apart(Eigen::Translation3d(0, 0, 2.1));  // faces 0.1 apart
  ContactPatch p;
  ASSERT_EQ(contact_patch(A, Isometry3d::Identity(), B, apart, 0.05, p), Status::Ok);
  EXPECT_EQ(p.size, 0);
  EXPECT_NEAR(p.depth, -0.1, 1e-12);
  ASSERT_EQ(contact_patch(A, Isometry3d::Identity(), B, apart, 0.2, p), Status::Ok);
  EXPECT_EQ(p.size, 4);  // the unit square, on A's top face
  EXPECT_EQ(p.feature_a.kind, ContactPatch::Feature::Kind::Face);
  EXPECT_EQ(p.feature_b.kind, ContactPatch::Feature::Kind::Face);
  EXPECT_NEAR(p.normal.z(), 1.0, 1e-15);
  for (int k = 0; k < p.size; ++k) EXPECT_NEAR(p.points[k].z(), 1.0, 1e-15);
  EXPECT_EQ(contact_patch(A, Isometry3d::Identity(), B, apart, -1e-9, p), Status::InvalidArgument);
  EXPECT_EQ(p.size, 0);
  EXPECT_EQ(contact_patch(A, Isometry3d::Identity(), B, apart, std::nan(""), p), Status::InvalidArgument);
  Isometry3d bad = apart;
  bad.linear()(0, 0) = std::nan("");
  EXPECT_EQ(contact_patch(A, Isometry3d::Identity(), B, bad, 0.2, p), Status::InvalidPose);
  bad = apart;
  bad.linear() *= 2;
  EXPECT_EQ(contact_patch(A, bad, B, apart, 0.2, p), Status::InvalidPose);
  EXPECT_EQ(contact_patch(empty, Isometry3d::Identity(), B, apart, 0.2, p), Status::TooFewPoints);
  EXPECT_EQ(p.size, 0);
  // Two 100-gon prisms face on face: 200 points of supporting sets, past the capacity.
  std::vector<Vector3d> prism;
  for (int k = 0; k < 100; ++k)
    for (double z : {0.0, 1.0}) prism.push_back({std::cos(2 * M_PI * k / 100), std::sin(2 * M_PI * k / 100), z});
  ConvexShape P;
  ASSERT_EQ(shape_from_points(prism, P), Status::Ok);
  EXPECT_EQ(contact_patch(P, Isometry3d::Identity(), P, Isometry3d(Eigen::Translation3d(0.1, 0, 1)), 0, p),
            Status::CapacityExceeded);
  EXPECT_EQ(p.size, 0);
  // Any margin, however large: the patch of the nearest sets.
  ASSERT_EQ(contact_patch(A, Isometry3d::Identity(), B, apart, HUGE_VAL, p), Status::Ok);
  EXPECT_EQ(p.size, 4);
}


// A pose is accepted orthonormal to 1e-9 (proper_rotation): the patch's normal along a face
// axis is still unit to rounding (it was the posed box's column, 4e-10 long).
TEST(ContactPatch, NormalIsUnitForPosesOrthonormalToTheirTolerance) {
  ConvexShape A, B, T;
  ASSERT_EQ(shape_from_box(Box{}, A), Status::Ok);
  ASSERT_EQ(shape_from_box(Box{}, B), Status::Ok);
  ASSERT_EQ(shape_from_triangle(Triangle{{-0.5, -0.5, 0}, {0.5, -0.5, 0}, {0, 0.5, 0}}, T), Status::Ok);
  Isometry3d loose = Isometry3d::Identity();
  loose.linear() *= 1 + 4e-10;
  const Isometry3d above(Eigen::Translation3d(0.2, 0.1, 2.05)), on(Eigen::Translation3d(0.2, 0.1, 1.05));
  ContactPatch p;
  ASSERT_EQ(contact_patch(A, loose, B, above, 0.1, p), Status::Ok);
  EXPECT_EQ(p.size, 4);
  EXPECT_NEAR(p.normal.norm(), 1.0, 4 * std::numeric_limits<double>::epsilon());
  ASSERT_EQ(contact_patch(A, loose, T, on, 0.1, p), Status::Ok);
  EXPECT_EQ(p.size, 3);
  EXPECT_NEAR(p.normal.norm(), 1.0, 4 * std::numeric_limits<double>::epsilon());
}

// Ties (tests/ties.hpp): boxes in exact contact (face on face, edge, corner; quarter-turned) and
// a box with a triangle touching it. The patch at margin 0 exists (an edge on an edge along an
// irrational normal once rounded to a gap of 4e-16 and lost it), its depth is the exact query's
// and never negative (they touch: rounding may not part them), its normal unit, A's and B's
// supporting planes along it the same plane to rounding, and every point on it.
TEST(ContactPatch, TouchingTiesHaveAPatchAtDepthZero) {
  std::mt19937_64 rng(5354);
  const int pairs = test::scaled(300, 30);
  for (int k = 0; k < pairs; ++k) {
    ConvexShape A, B;
    test::ties::touching_shapes(rng, k % 2 == 0, A, B);
    ASSERT_FALSE(A.empty() || B.empty());
    const std::string where = "pair " + std::to_string(k);
    ContactPatch patch;
    ASSERT_EQ(contact_patch(A, Isometry3d::Identity(), B, Isometry3d::Identity(), 0, patch), Status::Ok) << where;
    ASSERT_GT(patch.size, 0) << where;
    Proximity p;
    ASSERT_EQ(proximity(A, Isometry3d::Identity(), B, Isometry3d::Identity(), p), Status::Ok) << where;
    ASSERT_TRUE(p.intersecting) << where;  // (exact: tests/test_ties.cpp)
    EXPECT_GE(patch.depth, 0) << where;
    EXPECT_LE(patch.depth, 1e-15 * 16) << where;  // (lattice coordinates within 8)
    EXPECT_NEAR(patch.normal.norm(), 1, 1e-12) << where;
    // Each point on A's supporting plane along the normal, and on B's (they are the same plane).
    double top_a = -INFINITY, bottom_b = INFINITY;
    for (const auto& v : A.polytope().vertices) top_a = std::max(top_a, patch.normal.dot(v));
    for (const auto& v : B.polytope().vertices) bottom_b = std::min(bottom_b, patch.normal.dot(v));
    EXPECT_NEAR(top_a, bottom_b, 1e-12 * (1 + std::abs(top_a))) << where;
    for (int p = 0; p < patch.size; ++p) EXPECT_NEAR(patch.normal.dot(patch.points[p]), top_a, 1e-12 * (1 + std::abs(top_a))) << where;
  }
}

}  // namespace
}  // namespace minksum
