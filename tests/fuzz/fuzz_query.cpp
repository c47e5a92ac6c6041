// The proximity queries on boxes and triangles from arbitrary numbers (a first byte of 96 to
// 127: box pairs with B turned from A by a tiny angle), a clear status, or
// finite answers that agree with each other (distance >= 0, witnesses that realise it) and
// with brute force (kinds 0 to 2: the least exact distance over the pairs of surface
// triangles, test::exact_triangle_distance, and corner containment for a verdict of
// intersecting). Kinds
// 3 to 5 drive the coherent entry points (box pairs, box-triangle, prepared shapes) along a
// sequence of poses from the input (first byte 128, 129, 130), small steps and jumps, with one cache: the same status
// and verdict as the cold query at every step, and the same distance and depth to rounding;
// kind 5 also checks the contact patch at every step, and the time of impact of every motion,
// convex and against A's surface as a mesh: hits within the tolerance, misses by the band's
// contract (no pass within half the tolerance: sampled, confirmed by the exact distance).
// Kind 6 (first byte 240 and up): rounded shapes against their cores' exact distance.
//
// The oracle's triangle distances are first taken in double (test::rounded_triangle_distance:
// the exact enumeration's steps rounded), and exactly (GMP) only where that opinion fails a
// check: the input then runs again with the exact oracle, and fails only if a check fails
// there too. One input in 16 (by a hash of its bytes) runs exactly from the start, so that the
// rounded opinion's own errors meet the exact oracle as well. (GMP on every input held the
// target to 27-88 inputs a second; FUZZ_QUERY_EXACT=1 runs it so again. tests/fuzz/LEDGER.md.)
#include "fuzz_common.hpp"
#include "exact_distance.hpp"

#include <algorithm>
#include <array>
#include <initializer_list>
#include <limits>
#include <cstdlib>
#include <type_traits>

using namespace minksum;

namespace {

bool exact_oracle = false;  // this run's oracle: exact (GMP), or the rounded first opinion
long doubts = 0;            // inputs rerun exactly after the rounded opinion failed a check

struct Doubt {};  // a check failed on the rounded opinion: the input runs again exactly

// A check that failed: with the rounded oracle, a doubt (the rerun decides); exactly, a finding.
[[noreturn]] void fail(const char* what) {
  if (!exact_oracle) throw Doubt{};
  fuzz::fail(what);
}

// What a failed check prints, once: on the exact run.
template <class... Args>
void report(const char* format, Args... args) {
  if (exact_oracle) std::fprintf(stderr, format, args...);
}

double oracle_distance(const Eigen::Vector3d (&s)[3], const Eigen::Vector3d (&t)[3]) {
  return exact_oracle ? test::exact_triangle_distance(s, t) : test::rounded_triangle_distance(s, t);
}

Box box(fuzz::Bytes& in) {
  Box b;
  b.center = Eigen::Vector3d(in.number(), in.number(), in.number());
  b.half_extents = Eigen::Vector3d(in.number(), in.number(), in.number());
  Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
  if (q.norm() > 0 && std::isfinite(q.norm()))
    b.rotation = q.normalized().toRotationMatrix();
  else
    b.rotation = Eigen::Matrix3d::Constant(in.number());  // invalid on purpose
  return b;
}

Triangle triangle(fuzz::Bytes& in) {
  Triangle t;
  for (Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) *v = Eigen::Vector3d(in.number(), in.number(), in.number());
  return t;
}

// An operand as triangles over its corners (a box's 12 surface triangles, or the triangle).
int surface(const Box& b, Eigen::Vector3d (*out)[3]) {
  int n = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = 1 << (axis + 1) % 3, v = 1 << (axis + 2) % 3, base = side << axis;
      const int quad[4] = {base, base | u, base | u | v, base | v};
      for (int t = 0; t < 2; ++t) {
        out[n][0] = box_corner(b, quad[0]), out[n][1] = box_corner(b, quad[1 + t]),
        out[n][2] = box_corner(b, quad[2 + t]);
        ++n;
      }
    }
  return n;
}
int surface(const Triangle& t, Eigen::Vector3d (*out)[3]) {
  out[0][0] = t.a, out[0][1] = t.b, out[0][2] = t.c;
  return 1;
}

// Whether x lies in box b, within tol.
bool inside(const Box& b, const Eigen::Vector3d& x, double tol) {
  return ((b.rotation.transpose() * (x - b.center)).cwiseAbs() - b.half_extents).maxCoeff() <= tol;
}

// An operand's corners, and its edge directions and face normals (the candidate axes).
int corners(const Box& b, Eigen::Vector3d* out) {
  for (int k = 0; k < 8; ++k) out[k] = box_corner(b, k);
  return 8;
}
int corners(const Triangle& t, Eigen::Vector3d* out) {
  out[0] = t.a, out[1] = t.b, out[2] = t.c;
  return 3;
}
int directions(const Box& b, Eigen::Vector3d* edges, Eigen::Vector3d* normals, int& faces) {
  for (int k = 0; k < 3; ++k) edges[k] = normals[k] = b.rotation.col(k);
  faces = 3;
  return 3;
}
int directions(const Triangle& t, Eigen::Vector3d* edges, Eigen::Vector3d* normals, int& faces) {
  edges[0] = t.b - t.a, edges[1] = t.c - t.b, edges[2] = t.a - t.c;
  normals[0] = edges[0].cross(edges[1]);
  faces = 1;
  return 3;
}

// The penetration depth by the separating axis theorem: the least overlap of the two corner
// sets' projections over the face normals of both and the crosses of their edges (the facet
// normals of A (-) B: the minimum translation is along one of them), as an interval [lo, hi]
// that holds it despite rounding: an axis x cross y is turned by about eps |x| |y| / |x cross y|,
// which moves the projections by that times the reach (near-parallel edges at 1e83: 1e77).
// Crosses of edges past 1e154 have squares past the doubles: their lengths are taken stably.
template <class A, class B>
void sat_depth(const A& a, const B& b, double reach, double& lo, double& hi) {
  Eigen::Vector3d ca[8], cb[8], ea[3], eb[3], axes[3 + 3 + 9];
  double turn[3 + 3 + 9];
  int fa = 0, fb = 0;
  const int na = corners(a, ca), nb = corners(b, cb);
  directions(a, ea, axes, fa);
  directions(b, eb, axes + fa, fb);
  int n = fa + fb;
  for (int k = 0; k < n; ++k) turn[k] = 4;
  for (const auto& x : ea)
    for (const auto& y : eb) {
      const double cross = x.cross(y).stableNorm(), product = x.stableNorm() * y.stableNorm();
      if (cross > 1e-9 * product) turn[n] = 4 * product / cross, axes[n++] = x.cross(y);  // (parallel: no axis)
    }
  lo = hi = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    const double length = axes[k].stableNorm();  // (past 1e154 a plain norm squares to inf)
    if (!(length > 0)) continue;
    const Eigen::Vector3d u = axes[k] / length;
    double lo_a = INFINITY, hi_a = -INFINITY, lo_b = INFINITY, hi_b = -INFINITY;
    for (int i = 0; i < na; ++i) lo_a = std::min(lo_a, u.dot(ca[i])), hi_a = std::max(hi_a, u.dot(ca[i]));
    for (int i = 0; i < nb; ++i) lo_b = std::min(lo_b, u.dot(cb[i])), hi_b = std::max(hi_b, u.dot(cb[i]));
    const double overlap = std::min(hi_a - lo_b, hi_b - lo_a),
                 error = turn[k] * std::numeric_limits<double>::epsilon() * reach;
    lo = std::min(lo, overlap - error), hi = std::min(hi, overlap + error);
  }
}

// Brute force on an Ok answer of kinds 0 to 2: the distance is the least exact distance over
// pairs of surface triangles (when apart, the closest points lie on the surfaces); a verdict
// of intersecting needs surfaces that meet or a corner of one inside the other (a box holds
// the other operand whole). The tolerance is rounding: 1e-12 of the largest coordinate or
// extent (the corners carry eps of it, the queries a few hundred eps).
template <class A, class B>
void brute(const A& a, const B& b, const Proximity& p) {
  Eigen::Vector3d sa[12][3], sb[12][3];
  const int na = surface(a, sa), nb = surface(b, sb);
  double reach = 0;
  for (int i = 0; i < na; ++i)
    for (const auto& x : sa[i]) reach = std::max(reach, x.cwiseAbs().maxCoeff());
  for (int j = 0; j < nb; ++j)
    for (const auto& x : sb[j]) reach = std::max(reach, x.cwiseAbs().maxCoeff());
  const double tol = 1e-12 * reach;
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < na; ++i)
    for (int j = 0; j < nb; ++j) least = std::min(least, oracle_distance(sa[i], sb[j]));
  const auto contains = [&](const auto& outer, Eigen::Vector3d(*tris)[3], int n) {
    if constexpr (std::is_same_v<std::decay_t<decltype(outer)>, Box>) {
      for (int k = 0; k < n; ++k)
        if (inside(outer, tris[k][0], tol)) return true;
    }
    return false;
  };
  const bool meet = least <= tol || contains(a, sb, nb) || contains(b, sa, na);
  if (p.intersecting != meet && std::min(least, p.distance) <= tol) return;  // touching: either verdict
  if (p.intersecting != meet || (!p.intersecting && std::abs(p.distance - least) > tol)) {
    report("query: intersecting %d distance %.17g; brute force: meet %d least %.17g (tol %.3g)\n",
                 int(p.intersecting), p.distance, int(meet), least, tol);
    fail("the query differs from brute force");
  }
  // The depth against the separating axes, within their rounding (sat_depth), 1e-9 of the
  // reach, and near contact the rounding of a touching answer.
  if (p.intersecting) {
    double lo, hi;
    sat_depth(a, b, reach, lo, hi);
    // (At contact the depth carries the rounding `same` allows: 1024 eps reach^2 / gap, the gap
    // floored at sqrt(eps) reach; a 1e83 pair touching along a face read 2e-8 of the reach deep.)
    const double eps = std::numeric_limits<double>::epsilon(), gap = std::max(hi, std::sqrt(eps) * reach);
    const double slack = 1e-9 * reach + 1024 * eps * reach * std::max(1.0, reach / gap);
    if (std::isfinite(hi) && (p.penetration_depth < lo - slack || p.penetration_depth > std::max(hi, 0.0) + slack)) {
      report("query: depth %.17g; separating axes: [%.17g, %.17g] (reach %.3g)\n", p.penetration_depth,
                   lo, hi, reach);
      fail("the query's penetration depth differs from the separating axes'");
    }
  }
}

// The next motion of a sequence: a small step (the usual case), or a jump to anywhere.
Eigen::Isometry3d motion(fuzz::Bytes& in) {
  const uint8_t mode = in.take<uint8_t>();
  const double scale = mode < 200 ? 1.0 / 256 : 1.0;
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(1, scale * in.number(), scale * in.number(), scale * in.number());
  m.linear() = q.normalized().toRotationMatrix();  // (a NaN here is what the check must reject)
  m.translation() = scale * Eigen::Vector3d(in.number(), in.number(), in.number());
  return m;
}

// Coherent and cold answers of one step agree: status, verdict, distance and depth, the last
// two to their rounding: the closest points carry eps times the largest coordinate of the
// posed objects (`reach`), which turns the separating direction by eps reach / distance, and
// the supports along it by eps reach^2 / distance (needles 1e5 times longer than their
// distance leave only that). Below a gap of sqrt(eps) reach that bound passes the gap itself,
// so the gap is floored there: at contact both answers are within 1024 sqrt(eps) reach of 0.
void same(Status cold_status, const Proximity& cold, Status warm_status, const Proximity& warm, double reach) {
  if (cold_status != warm_status) fail("the coherent query's status differs from the cold one");
  if (cold_status != Status::Ok) return;
  fuzz::check(warm);
  if (cold.intersecting != warm.intersecting) {
    std::fprintf(
        stderr,
        "cold: intersecting %d distance %.17g depth %.17g; coherent: intersecting %d distance %.17g depth %.17g\n",
        int(cold.intersecting), cold.distance, cold.penetration_depth, int(warm.intersecting), warm.distance,
        warm.penetration_depth);
    fail("the coherent query's verdict differs from the cold one");
  }
  const double scale = 1 + cold.max_distance + cold.point_a.cwiseAbs().maxCoeff() + cold.point_b.cwiseAbs().maxCoeff();
  const double gap =
      std::max({cold.distance, cold.penetration_depth, std::sqrt(std::numeric_limits<double>::epsilon()) * reach});
  const double tol = 1e-9 * scale + 1024 * std::numeric_limits<double>::epsilon() * reach * std::max(1.0, reach / gap);
  if (std::abs(cold.distance - warm.distance) > tol ||
      std::abs(cold.penetration_depth - warm.penetration_depth) > tol) {
    report("cold: intersecting %d distance %.17g depth %.17g; coherent: distance %.17g depth %.17g\n",
                 int(cold.intersecting), cold.distance, cold.penetration_depth, warm.distance, warm.penetration_depth);
    fail("the coherent query's distance or depth differs from the cold one");
  }
}

// A patch's normal is unit and its points lie on A's supporting plane along it (within slack).
void on_plane(const ConvexShape& A, const ContactPatch& p, double slack) {
  if (p.size == 0) return;
  if (!p.normal.allFinite() || std::abs(p.normal.norm() - 1) > 1e-9) fail("a patch's normal is not unit");
  double top = -std::numeric_limits<double>::infinity();
  for (const auto& v : A.polytope().vertices) top = std::max(top, p.normal.dot(v));
  for (int k = 0; k < p.size; ++k)
    if (!p.points[k].allFinite() || std::abs(p.normal.dot(p.points[k]) - top) > slack)
      fail("a patch point off A's supporting plane");
}

// Kind 5's contact patch at each step: the query's status (InvalidArgument for a margin < 0
// or NaN), the cold query's depth (minus its distance apart) exactly, finite points on A's
// supporting plane along a unit normal, and points exactly where the shapes lie within the
// margin; the coherent patch the same to the slack; the reduction at most 4 of its points.
void patch(const ConvexShape& A, const ConvexShape& B, const Eigen::Isometry3d& pose, Status sc, const Proximity& cold,
           double margin, double reach, ProximityCache& cache) {
  ContactPatch p, q;
  const Status s = contact_patch(A, Eigen::Isometry3d::Identity(), B, pose, margin, p);
  // The coherent patch: the cold one's status, depth (to the certificates' slack) and points.
  if (contact_patch(A, Eigen::Isometry3d::Identity(), B, pose, margin, cache, q) != s)
    fail("the coherent patch's status differs from the cold one's");
  const double slack = 1e-9 * (1 + reach);
  if (s == Status::Ok && !(std::abs(q.depth - p.depth) <= slack))
    fail("the coherent patch's depth differs from the cold one's");
  if (s == Status::Ok && std::abs(p.depth + margin) > slack && (q.size > 0) != (p.size > 0))
    fail("the coherent patch is empty where the cold one is not, or the reverse");
  // Its reduction: at most 4 of its points.
  ContactPatch r = p;
  reduce_contact_patch(r);
  if (r.size > 4 || (p.size <= 4 && r.size != p.size)) fail("a reduced patch of the wrong size");
  for (int k = 0; k < r.size; ++k)
    if (std::find(p.points, p.points + p.size, r.points[k]) == p.points + p.size)
      fail("a reduced patch with a point not in the patch");
  const Status expected = sc != Status::Ok ? sc : !(margin >= 0) ? Status::InvalidArgument : Status::Ok;
  if (s != expected) fail("the patch's status differs from the query's");
  if (s != Status::Ok) {
    if (p.size != 0) fail("a patch that failed has points");
    return;
  }
  if (p.size < 0 || p.size > ContactPatch::kCapacity) fail("a patch's size is outside its capacity");
  if (p.depth != (cold.intersecting ? cold.penetration_depth : -cold.distance))
    fail("the patch's depth differs from the query's");
  if ((p.size > 0) != (cold.intersecting || cold.distance <= margin))
    fail("a patch where the shapes are beyond the margin, or none within it");
  on_plane(A, p, slack), on_plane(A, q, slack);
}

// The own-form patches (a box and a box, a box and a triangle: their separating axes) against
// the general path on the same polytopes: the same status, the depth to rounding, a patch on
// both or neither (away from the margin's edge), points on A's supporting plane.
// A box or triangle shape in its own form and as a general polytope (built once a sequence).
struct OwnForm {
  ConvexShape own, general;
  bool ok = false;
  OwnForm(Status s, const ConvexShape& built) : own(built) {
    ok = s == Status::Ok && shape_from_polytope(own.polytope(), general) == Status::Ok;
  }
};

void own_form_patch(const OwnForm& a, const OwnForm& b, const Eigen::Isometry3d& pose, double margin) {
  if (!a.ok || !b.ok) return;
  const ConvexShape &A = a.own, &B = b.own, &GA = a.general, &GB = b.general;
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  ContactPatch p, q;
  const Status s = contact_patch(A, identity, B, pose, margin, p);
  if (s != contact_patch(GA, identity, GB, pose, margin, q)) fail("an own-form patch's status differs");
  if (s != Status::Ok) return;
  double reach = 0;
  for (const auto& v : A.polytope().vertices) reach = std::max(reach, v.cwiseAbs().maxCoeff());
  for (const auto& v : B.polytope().vertices) reach = std::max(reach, (pose * v).cwiseAbs().maxCoeff());
  if (!std::isfinite(reach)) return;
  const double slack = 1e-9 * (1 + reach);
  if (!(std::abs(p.depth - q.depth) <= slack)) fail("an own-form patch's depth differs from the general one's");
  if (std::abs(q.depth + margin) > slack && (p.size > 0) != (q.size > 0))
    fail("an own-form patch is empty where the general one is not, or the reverse");
  on_plane(A, p, slack);
}

// B's pose at time t of the motion from `from` to `to`, as time_of_impact moves it: the origin
// along the segment, the rotation about one axis (`turn`, from's rotation to to's).
Eigen::Isometry3d pose_at(const Eigen::Isometry3d& from, const Eigen::Isometry3d& to, const Eigen::AngleAxisd& turn,
                          double t) {
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.linear() = from.linear() * Eigen::AngleAxisd(t * turn.angle(), turn.axis()).toRotationMatrix();
  at.translation() = (1 - t) * from.translation() + t * to.translation();
  return at;
}

// The gap along n from the highest of the points a to the lowest of B's vertices at pose `at`:
// a hit's normal separates them to its tolerance (>= -tolerance, less rounding).
template <class Points>
double gap_along(const Points& a, const ConvexShape& B, const Eigen::Isometry3d& at, const Eigen::Vector3d& n) {
  double top = -std::numeric_limits<double>::infinity(), bottom = -top;
  for (const Eigen::Vector3d& x : a) top = std::max(top, n.dot(x));
  for (const Eigen::Vector3d& x : B.polytope().vertices) bottom = std::min(bottom, n.dot(at * x));
  return bottom - top;
}

// The exact distance of A and B at B's pose `at`: the least exact distance over their fanned
// faces (test::exact_triangle_distance, not the library); 0 where the query says they overlap.
double exact_gap(const ConvexShape& A, const ConvexShape& B, const Eigen::Isometry3d& at) {
  const auto fan = [](const ConvexPolytope& p, const Eigen::Isometry3d& pose, std::vector<std::array<Eigen::Vector3d, 3>>& out) {
    for (const auto& f : p.faces)
      for (size_t k = 1; k + 1 < f.loop.size(); ++k)
        out.push_back({pose * p.vertices[size_t(f.loop[0])], pose * p.vertices[size_t(f.loop[k])],
                       pose * p.vertices[size_t(f.loop[k + 1])]});
  };
  thread_local std::vector<std::array<Eigen::Vector3d, 3>> ta, tb;  // (kept: no allocation per call)
  ta.clear(), tb.clear();
  fan(A.polytope(), Eigen::Isometry3d::Identity(), ta), fan(B.polytope(), at, tb);
  double least = std::numeric_limits<double>::infinity();
  for (const auto& x : ta)
    for (const auto& y : tb) {
      const Eigen::Vector3d s[3] = {x[0], x[1], x[2]}, t[3] = {y[0], y[1], y[2]};
      least = std::min(least, oracle_distance(s, t));
    }
  return least;
}

// The band's contract (TimeOfImpact) on a motion that `hit` says never brings A and B within
// tolerance / 2: 16 sampled times by the query, and any sample inside that confirmed by the
// exact distance (exact_gap). (The sweeps may differ in the band: between tolerance / 2 and
// the tolerance either answer holds.)
void no_pass_within_half(const ConvexShape& A, const ConvexShape& B, const Eigen::Isometry3d& from,
                         const Eigen::Isometry3d& to, double tolerance, double reach, const char* which) {
  const Eigen::AngleAxisd turn(Eigen::Matrix3d(from.linear().transpose() * to.linear()));
  const double slack = 1e-9 * (1 + reach);
  for (int k = 0; k <= 16; ++k) {
    const Eigen::Isometry3d at = pose_at(from, to, turn, k / 16.0);
    Proximity p;
    if (proximity(A, Eigen::Isometry3d::Identity(), B, at, p, Want::Patch) != Status::Ok) continue;
    if (!(p.intersecting || p.distance < 0.5 * tolerance - slack)) continue;
    if (const double d = exact_gap(A, B, at); d < 0.5 * tolerance - slack && !p.intersecting) {
      report("%s: no hit, but at %d/16 of the motion the shapes are %.17g apart (tolerance %.17g)\n",
                   which, k, d, tolerance);
      fail("a time of impact misses a pass within half its tolerance");
    } else if (p.intersecting) {
      fail("a time of impact misses an overlap");
    }
  }
}

// Kind 5's time of impact for B's motion from one pose to the next: the proximity query's
// status; a time in [0, 1], 0 where they overlap at the start; within the tolerance at it,
// along a unit normal; and no overlap deeper than rounding at 8 times before it. Then against
// A's surface as a mesh, at the same tolerance.
void impact(const ConvexShape& A, const Octree& surface, const ConvexShape& B, const Eigen::Isometry3d& from,
            const Eigen::Isometry3d& to, Status expected, double reach) {
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  TimeOfImpact toi;
  const Status s = time_of_impact(A, identity, identity, B, from, to, toi);
  if (s != expected) fail("the time of impact's status differs from the query's");
  if (s != Status::Ok) return;
  if (!(toi.time >= 0 && toi.time <= 1)) fail("a time of impact outside [0, 1]");
  Proximity start;
  if (proximity(A, identity, B, from, start, Want::Patch) != Status::Ok) return;
  if (start.intersecting && (!toi.hit || toi.time != 0)) fail("overlapping at the start, not time 0");
  // (B's pose at a time as time_of_impact moves it: the origin along the segment, the rotation
  // about one axis.)
  const Eigen::AngleAxisd turn(Eigen::Matrix3d(from.linear().transpose() * to.linear()));
  // A miss is checked too: no pass within half the tolerance (the band's contract).
  if (!toi.hit && toi.converged) no_pass_within_half(A, B, from, to, toi.tolerance, reach, "convex");
  if (toi.hit && !(toi.distance <= toi.tolerance)) fail("a time of impact farther apart than its tolerance");
  if (toi.hit && (!toi.normal.allFinite() || std::abs(toi.normal.norm() - 1) > 1e-9))
    fail("a time of impact's normal");
  // (A normal from witnesses d apart turns by eps reach / d by their rounding, which moves the
  // planes along it by eps reach^2 / d (TimeOfImpact::normal); at d = 0 nothing is checked. At
  // time 0 the normal is the contact patch's, from the exact query's witnesses, which may lie
  // far nearer than the advancement's distance: that one bounds the distance from above.)
  const double eps = std::numeric_limits<double>::epsilon(), slack = 1e-9 * (1 + reach);
  const auto turned = [&](double d) {
    return d > 0 ? slack + 1024 * eps * reach * std::max(1.0, reach / d) : std::numeric_limits<double>::infinity();
  };
  if (toi.hit && !start.intersecting &&
      gap_along(A.polytope().vertices, B, pose_at(from, to, turn, toi.time), toi.normal) <
          -(toi.tolerance + turned(toi.time == 0 ? std::min(toi.distance, start.distance) : toi.distance)))
    fail("a time of impact's normal is no separating plane");
  for (int k = 0; k < 8 && toi.hit && toi.time > 0; ++k) {
    const Eigen::Isometry3d at = pose_at(from, to, turn, toi.time * k / 8);
    Proximity p;
    if (proximity(A, identity, B, at, p, Want::Patch) == Status::Ok && p.intersecting &&
        p.penetration_depth > 1e-9 * (1 + reach))
      fail("overlapping before the time of impact");
  }
  // A's surface as a mesh: where B starts clear of A, the same hit (within the tolerance of A
  // at it, apart from A before it: the surface is A's boundary).
  TimeOfImpact mesh;
  const Status sm = time_of_impact(surface, identity, B, from, to, mesh, toi.tolerance);
  if (sm != s) fail("the mesh time of impact's status differs from the convex one's");
  if (!(toi.time > 0 || !toi.hit) || !toi.converged || !mesh.converged) return;
  // Where the mesh sweep misses, no pass within half the tolerance (the convex one may hit in
  // the band; its miss was checked above).
  if (!mesh.hit && toi.hit) no_pass_within_half(A, B, from, to, toi.tolerance, reach, "mesh");
  if (!mesh.hit) return;
  if (!(mesh.time >= 0 && mesh.time <= 1) || mesh.triangle < 0) fail("a mesh time of impact's time or triangle");
  const Eigen::Isometry3d at = pose_at(from, to, turn, mesh.time);
  const std::array<int, 3>& hit = surface.triangles[size_t(mesh.triangle)];
  const Eigen::Vector3d corners[3] = {surface.vertices[size_t(hit[0])], surface.vertices[size_t(hit[1])],
                                      surface.vertices[size_t(hit[2])]};
  if (gap_along(corners, B, at, mesh.normal) < -(mesh.tolerance + turned(mesh.distance)))
    fail("a mesh time of impact's normal is no separating plane of its triangle");
  Proximity p;
  if (proximity(A, identity, B, at, p, Want::Patch) == Status::Ok && !p.intersecting &&
      p.distance > mesh.tolerance * (1 + 1e-6) + 1e-12 * (1 + reach))
    fail("a mesh time of impact farther apart than its tolerance");
}

// Kinds 3-5: up to 12 motions of B, each answered cold and through one cache (kind 5: and its
// contact patch, cold, coherent and reduced, the own-form patches of its boxes and triangle, and
// the time of impact of each motion).
void sequence(fuzz::Bytes& in, int kind) {
  const Box a = box(in), body = box(in);
  const Triangle tri = triangle(in);
  ConvexShape A, B;
  Octree surface;
  if (kind == 5) {
    std::vector<Eigen::Vector3d> pa, pb;
    const int na = 4 + in.take<uint8_t>() % 12, nb = 4 + in.take<uint8_t>() % 12;
    for (int k = 0; k < na; ++k) pa.emplace_back(in.number(), in.number(), in.number());
    for (int k = 0; k < nb; ++k) pb.emplace_back(in.number(), in.number(), in.number());
    if (shape_from_points(pa, A) != Status::Ok || shape_from_points(pb, B) != Status::Ok) return;
    std::vector<std::array<int, 3>> triangles;  // A's faces, fanned
    for (const auto& f : A.polytope().faces)
      for (size_t k = 1; k + 1 < f.loop.size(); ++k) triangles.push_back({f.loop[0], f.loop[k], f.loop[k + 1]});
    if (build_octree(A.polytope().vertices, triangles, surface) != Status::Ok) return;
  }
  const double margin = kind == 5 ? in.number() : 0;
  ConvexShape shapes[3];  // kind 5: the boxes a and body and the triangle, each in two forms
  const auto built = [&](Status s, int k) { return OwnForm(s, shapes[k]); };
  const OwnForm own[3] = {built(kind == 5 ? shape_from_box(a, shapes[0]) : Status::InvalidBox, 0),
                          built(kind == 5 ? shape_from_box(body, shapes[1]) : Status::InvalidBox, 1),
                          built(kind == 5 ? shape_from_triangle(tri, shapes[2]) : Status::InvalidBox, 2)};
  ProximityCache cache, patch_cache;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const auto largest = [](std::initializer_list<Eigen::Vector3d> v) {
    double m = 0;
    for (const auto& x : v) m = std::max(m, x.cwiseAbs().maxCoeff());
    return m;
  };
  for (int step = 0; step < 12 && in.n > 0; ++step) {
    const Eigen::Isometry3d before = pose;
    pose = pose * motion(in);
    Proximity cold, warm;
    Status sc, sw;
    double reach = 0;
    if (kind == 3) {
      Box b = body;
      b.center = pose * body.center, b.rotation = pose.linear() * body.rotation;
      sc = proximity(a, b, cold), sw = proximity(a, b, cache, warm);
      reach = largest({a.center, b.center}) + a.half_extents.cwiseAbs().sum() + b.half_extents.cwiseAbs().sum();
    } else if (kind == 4) {
      const Triangle t{pose * tri.a, pose * tri.b, pose * tri.c};
      sc = proximity(a, t, cold), sw = proximity(a, t, cache, warm);
      reach = largest({a.center, t.a, t.b, t.c}) + a.half_extents.cwiseAbs().sum();
    } else {
      sc = proximity(A, Eigen::Isometry3d::Identity(), B, pose, cold, Want::Patch);
      sw = proximity(A, Eigen::Isometry3d::Identity(), B, pose, cache, warm, Want::Patch);
      for (const auto& v : A.polytope().vertices) reach = std::max(reach, largest({v}));
      for (const auto& v : B.polytope().vertices) reach = std::max(reach, largest({pose * v}));
    }
    if (!std::isfinite(reach)) reach = 0;
    same(sc, cold, sw, warm, reach);
    if (kind == 5) {
      patch(A, B, pose, sc, cold, margin, reach, patch_cache);
      if (step > 0)
        impact(A, surface, B, before, pose, check_pose(before) != Status::Ok ? check_pose(before) : sc, reach);
      // The same motions on the sequence's boxes and triangle.
      own_form_patch(own[0], own[1], pose, margin);
      own_form_patch(own[0], own[2], pose, margin);
      own_form_patch(own[2], own[0], pose, margin);
    }
  }
}

// The lower levels of a query (Want): the same status, verdict and (Distance) distance, depth
// and direction as the answer with witnesses, bit for bit, and the fields past them unset.
template <class A, class B>
void levels(const A& a, const B& b, Status s, const Proximity& p) {
  Proximity verdict, distance;
  if (proximity(a, b, verdict, Want::Verdict) != s || proximity(a, b, distance, Want::Distance) != s)
    fail("a level's status differs from the witnesses'");
  if (s != Status::Ok) return;
  if (verdict.intersecting != p.intersecting || distance.intersecting != p.intersecting)
    fail("a level's verdict differs from the witnesses'");
  if (!(distance.distance == p.distance && distance.penetration_depth == p.penetration_depth &&
        distance.penetration_direction == p.penetration_direction))
    fail("Want::Distance's distance or depth differs from the witnesses'");
  if (verdict.distance != 0 || verdict.penetration_depth != 0 || !distance.point_a.isZero() || !distance.point_b.isZero())
    fail("a level set a field it was not asked for");
}

}  // namespace

// A rounded operand of kind 6: a sphere, a capsule, a rounded box or a swept triangle, its
// radius and lengths as the input gives them, and its core's surface as triangles in the world
// (a point or segment core: one flat triangle), for the oracle.
struct RoundedOperand {
  ConvexShape shape;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  Eigen::Vector3d tri[12][3];
  int n = 0;
  bool is_box = false;
  Box placed;  // the box's, placed (is_box)
};

Status rounded_operand(fuzz::Bytes& in, RoundedOperand& out) {
  const uint8_t kind = in.take<uint8_t>() % 4;
  ConvexShape core;
  Status s;
  const double r = in.number();
  Box b;
  Triangle t;
  if (kind == 0) {
    s = shape_from_sphere(r, out.shape);
  } else if (kind == 1) {
    s = shape_from_capsule(in.number(), r, out.shape);
  } else {
    if (kind == 2) b = box(in), s = shape_from_box(b, core);
    if (kind == 3) t = triangle(in), s = shape_from_triangle(t, core);
    if (s == Status::Ok) s = shape_with_radius(core, r, out.shape);
  }
  if (s != Status::Ok) {
    if (!out.shape.empty()) fail("a shape that failed is not empty");
    return s;
  }
  Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
  if (q.norm() > 0 && std::isfinite(q.norm())) out.pose.linear() = q.normalized().toRotationMatrix();
  out.pose.translation() = Eigen::Vector3d(in.number(), in.number(), in.number());
  if (kind == 2) {
    out.is_box = true, out.placed = b;
    out.placed.center = out.pose * b.center, out.placed.rotation = out.pose.linear() * b.rotation;
    out.n = surface(out.placed, out.tri);
  } else if (kind == 3) {
    out.n = surface(Triangle{out.pose * t.a, out.pose * t.b, out.pose * t.c}, out.tri);
  } else {
    const std::vector<Eigen::Vector3d>& v = out.shape.polytope().vertices;
    out.tri[0][0] = out.pose * v.front(), out.tri[0][1] = out.tri[0][2] = out.pose * v.back();
    out.n = 1;
  }
  return Status::Ok;
}

// Kind 6 (first byte 240 and up): two rounded operands (rounded_operand), their proximity
// against the cores' exact distance (test::exact_triangle_distance over their surfaces, a box
// holding the other's first point) less the radii, within rounding of the largest coordinate
// and radius; the cached query's verdict and distance the cold one's; the contact patch's
// status and points; and B's time of impact along a step, a hit within the tolerance.
void rounded(fuzz::Bytes& in) {
  RoundedOperand a, b;
  if (rounded_operand(in, a) != Status::Ok || rounded_operand(in, b) != Status::Ok) return;
  Proximity p;
  const Status s = proximity(a.shape, a.pose, b.shape, b.pose, p);
  if (s != Status::Ok) {
    if (s != Status::InvalidPose) fail("a rounded query refused valid shapes for another reason than a pose");
    return;
  }
  double reach = a.shape.radius() + b.shape.radius();
  for (const RoundedOperand* x : {&a, &b})
    for (int i = 0; i < x->n; ++i)
      for (const auto& v : x->tri[i]) reach = std::max(reach, v.cwiseAbs().maxCoeff());
  fuzz::check(p, reach);
  const double tol = 1e-10 * reach, r = a.shape.radius() + b.shape.radius();
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < b.n; ++j) least = std::min(least, oracle_distance(a.tri[i], b.tri[j]));
  const double surfaces = least;  // (the cores' surfaces: a mesh of B's is a surface)
  if ((a.is_box && inside(a.placed, b.tri[0][0], 0)) || (b.is_box && inside(b.placed, a.tri[0][0], 0))) least = 0;
  const double signed_gap = p.intersecting ? -p.penetration_depth : p.distance;
  // Cores apart: the gap is their distance less the radii; meeting: deeper than the radii.
  const bool wrong = least > tol ? std::abs(signed_gap - (least - r)) > tol : signed_gap > -r + tol;
  if (wrong) {
    report("rounded: intersecting %d distance %.17g depth %.17g; cores %.17g apart, radii %.17g\n",
                 int(p.intersecting), p.distance, p.penetration_depth, least, r);
    fail("the rounded query differs from the cores' exact distance less the radii");
  }
  // The difference of rounded shapes holds the origin exactly when they meet; a mesh of B's
  // core surface is A's distance from those triangles.
  MinkowskiSum m;
  const Status ms = minkowski_difference(a.shape, a.pose, b.shape, b.pose, m);
  if (ms == Status::Ok && std::abs(least - r) > tol && contains(m, Eigen::Vector3d::Zero()) != (least <= r)) {
    report("rounded difference: contains(origin) %d; cores %.17g apart, radii %.17g\n", int(!(least <= r)), least, r);
    fail("the rounded difference's contains(origin) differs from the cores' exact distance");
  }
  if (ms == Status::Ok && !(penetration_along(m, Eigen::Vector3d::UnitX()) >= 0))
    fail("a rounded penetration_along is negative or NaN");
  if (ms != Status::Ok && ms != Status::Unsupported && ms != Status::DegenerateResult && ms != Status::HullFailed)
    fail("a rounded difference failed on valid shapes");
  std::vector<Eigen::Vector3d> corners;
  std::vector<std::array<int, 3>> faces;
  for (int j = 0; j < b.n; ++j) {
    for (const auto& v : b.tri[j]) corners.push_back(v);
    faces.push_back({3 * j, 3 * j + 1, 3 * j + 2});
  }
  Octree tree;
  MeshDistance md;
  if (build_octree(corners, faces, tree) != Status::Ok) tree = Octree{};
  if (!tree.nodes.empty() && mesh_distance(tree, Eigen::Isometry3d::Identity(), a.shape, a.pose, md) == Status::Ok) {
    // (A solid box holding a corner of B's surface holds part of a triangle: they meet.)
    const double core = a.is_box && inside(a.placed, b.tri[0][0], 0) ? 0.0 : surfaces;
    const double expected = std::max(0.0, core - a.shape.radius());
    if (std::abs(core - a.shape.radius()) > tol && std::abs(md.distance - expected) > tol) {
      report("rounded mesh: distance %.17g, expected %.17g\n", md.distance, expected);
      fail("the shape-mesh distance differs from the exact distance of the core to the triangles");
    }
  }
  // Mesh contact of A with that mesh: it touches exactly when the core comes within the radius
  // of B's triangles; a finite depth, a unit direction; moved by the depth along it, the core
  // lies at least the radius from each triangle that was within it.
  MeshWorkspace ws;
  MeshContact mc;
  const double ra = a.shape.radius();
  const auto core_to = [&](int j, const Eigen::Vector3d& shift) {  // B's triangle j from A's core moved
    if (a.is_box && inside(a.placed, b.tri[j][0] - shift, 0)) return 0.0;
    double d = std::numeric_limits<double>::infinity();
    for (int i = 0; i < a.n; ++i) {
      Eigen::Vector3d moved[3] = {a.tri[i][0] + shift, a.tri[i][1] + shift, a.tri[i][2] + shift};
      d = std::min(d, oracle_distance(moved, b.tri[j]));
    }
    return d;
  };
  if (!tree.nodes.empty() && (make_workspace(tree, tree, ws), true) &&
      mesh_contact(tree, Eigen::Isometry3d::Identity(), a.shape, a.pose, ws, mc) == Status::Ok) {
    const double core = a.is_box && inside(a.placed, b.tri[0][0], 0) ? 0.0 : surfaces;
    if (std::abs(core - ra) > tol && mc.intersecting != (core <= ra))
      fail("a rounded mesh contact's verdict differs from the exact distance of the core to the triangles");
    if (mc.intersecting && (!(mc.penetration_depth >= 0) || !std::isfinite(mc.penetration_depth) ||
                            (!mc.penetration_direction.isZero() && std::abs(mc.penetration_direction.norm() - 1) > 1e-9)))
      fail("a rounded mesh contact's depth or direction is not finite or not unit");
    const Eigen::Vector3d shift = mc.penetration_depth * mc.penetration_direction;
    const double moved_tol = tol + 1e-12 * mc.penetration_depth;
    for (int j = 0; j < b.n && mc.intersecting && !shift.isZero(); ++j)
      if (core_to(j, Eigen::Vector3d::Zero()) <= ra - tol && core_to(j, shift) < ra - moved_tol) {
        report("rounded mesh contact: depth %.17g leaves triangle %d at %.17g, radius %.17g\n",
                     mc.penetration_depth, j, core_to(j, shift), ra);
        fail("a rounded mesh contact's depth does not clear the triangles it touched");
      }
  }
  ProximityCache cache;
  Proximity q;
  for (int k = 0; k < 2; ++k)
    if (proximity(a.shape, a.pose, b.shape, b.pose, cache, q) != Status::Ok) fail("the cached query refused");
  const double cached_gap = q.intersecting ? -q.penetration_depth : q.distance;
  if (std::abs(cached_gap - signed_gap) > tol) fail("the cached rounded query differs from the cold one");
  // The patch within a margin from the input: a clear status, finite points.
  ContactPatch patch;
  const Status ps = contact_patch(a.shape, a.pose, b.shape, b.pose, std::abs(in.number()), patch);
  if (ps != Status::Ok && ps != Status::CapacityExceeded && ps != Status::InvalidArgument)
    fail("the rounded patch failed on valid shapes");
  for (int k = 0; k < patch.size; ++k)
    if (!fuzz::finite(patch.points[k])) fail("a rounded patch point is not finite");
  // B translating by a step from the input: a hit's cores are within the radii and the
  // tolerance (and rounding) of each other.
  Eigen::Isometry3d b1 = b.pose;
  b1.translation() += Eigen::Vector3d(in.number(), in.number(), in.number());
  TimeOfImpact toi;
  if (time_of_impact(a.shape, a.pose, a.pose, b.shape, b.pose, b1, toi) != Status::Ok) return;
  if (!(toi.time >= 0 && toi.time <= 1) || !fuzz::finite(toi.point_a) || !fuzz::finite(toi.point_b))
    fail("a rounded time of impact out of [0, 1] or not finite");
  if (!toi.hit) return;
  RoundedOperand at = b;
  const Eigen::Vector3d moved = toi.time * (b1.translation() - b.pose.translation());
  for (int i = 0; i < at.n; ++i)
    for (auto& v : at.tri[i]) v += moved;
  if (at.is_box) at.placed.center += moved;
  double near = std::numeric_limits<double>::infinity();
  for (int i = 0; i < a.n; ++i)
    for (int j = 0; j < at.n; ++j) near = std::min(near, oracle_distance(a.tri[i], at.tri[j]));
  if ((a.is_box && inside(a.placed, at.tri[0][0], 0)) || (at.is_box && inside(at.placed, a.tri[0][0], 0)))
    near = 0;  // (one core holds the other: their surfaces' distance is not theirs)
  if (near - r > toi.tolerance + 1e-9 * (reach + moved.norm())) {
    report("rounded toi: hit at %.17g with the cores %.17g apart, radii %.17g, tolerance %.3g\n",
                 toi.time, near, r, toi.tolerance);
    fail("a rounded time of impact hit farther apart than the tolerance");
  }
}

// One input, with the oracle as exact_oracle says.
void run(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const uint8_t first = in.take<uint8_t>();
  if (first >= 240) {
    rounded(in);
    return;
  }
  if (first >= 128) {  // (below 128: the single queries, as the older corpus files expect)
    sequence(in, 3 + (first - 128) % 3);
    return;
  }
  const uint8_t kind = first % 3;
  Proximity p;
  Status s;
  if (kind == 0) {
    const Box a = box(in);
    Box b = box(in);
    if (first >= 96) {  // B turned from A by 10^-1 ... 10^-10 rad: nearly parallel edges everywhere
      const int e = in.take<uint8_t>() % 10;
      const Eigen::Vector3d axis(in.number(), in.number(), in.number());
      if (axis.norm() > 0 && std::isfinite(axis.norm()))
        b.rotation = a.rotation * Eigen::AngleAxisd(std::pow(10.0, -1.0 - e), axis.normalized()).toRotationMatrix();
    }
    if ((s = proximity(a, b, p)) == Status::Ok) fuzz::check(p), brute(a, b, p);
    levels(a, b, s, p);
  } else if (kind == 1) {
    const Box a = box(in);
    const Triangle t = triangle(in);
    if ((s = proximity(a, t, p)) == Status::Ok) fuzz::check(p), brute(a, t, p);
    levels(a, t, s, p);
  } else {
    const Triangle a = triangle(in), b = triangle(in);
    if ((s = proximity(a, b, p)) == Status::Ok) fuzz::check(p), brute(a, b, p);
  }
}

long inputs = 0, exact_runs = 0;  // for the ledger: how often the exact oracle ran

bool always_exact = false;  // FUZZ_QUERY_EXACT=1: every input exactly (the target before the rounded oracle)

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  const char* exact = std::getenv("FUZZ_QUERY_EXACT");
  always_exact = exact && exact[0] == '1';
  std::atexit([] {
    std::fprintf(stderr, "fuzz_query: %ld inputs, %ld run with the exact oracle (%ld of them after a doubt)\n", inputs,
                 exact_runs, doubts);
  });
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  ++inputs;
  uint32_t hash = 2166136261u;  // FNV-1a: the same inputs are sampled on every run
  for (size_t k = 0; k < size; ++k) hash = (hash ^ data[k]) * 16777619u;
  exact_oracle = always_exact || hash % 16 == 0;
  try {
    run(data, size);
  } catch (const Doubt&) {
    exact_oracle = true, ++doubts;
    run(data, size);
  }
  exact_runs += exact_oracle;
  return 0;
}
