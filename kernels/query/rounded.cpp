// The posed queries' entry points: a shape is a core swept by a ball of its radius, so two
// shapes' proximity is their cores' with the radii added. For a convex K and a ball B(r), the
// signed distance of a point to K (+) B(r) is its signed distance to K minus r (the support of
// a Minkowski sum is the sum of the supports, the paper's Section 3), so the distance, the
// depth and their direction stay exact, and each witness moves along that direction by its
// shape's radius. Point and segment cores (spheres', capsules') have no faces: segment_core.cpp
// reads them against the other core.

#include <minksum/query.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "query/cache_kinds.hpp"
#include "query/core_query.hpp"
#include "query/rounded.hpp"
#include "query/segment_core.hpp"
#include "shape/shape_data.hpp"

namespace minksum {

using Eigen::Vector3d;

namespace {

const detail::ShapeData& data_of(const ConvexShape& s) { return *detail::ShapeAccess::data(s); }

// Whether a pair goes past the polytope cores' path: a radius, or a point or segment core.
bool rounded(const ConvexShape& a, const ConvexShape& b) {
  return a.radius() > 0 || b.radius() > 0 || !data_of(a).has_faces() || !data_of(b).has_faces();
}

// A sphere's core is the body origin, a capsule's the segment between -h and h on the body z
// axis (shape_from_sphere, shape_from_capsule).
detail::Segment placed_segment(const ConvexShape& s, const Eigen::Isometry3d& pose) {
  const Vector3d& t = pose.translation();
  const double h = s.polytope().vertices.back().z();
  if (h == 0) return {t, t};
  const Vector3d half = h * pose.linear().col(2);
  return {t - half, t + half};
}

// The farthest pair of a point or segment core (A) and any core (B), world frame.
void segment_farthest(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                      const Eigen::Isometry3d& pose_b, Proximity& out) {
  const detail::Segment s = placed_segment(a, pose_a);
  for (const Vector3d& v : b.polytope().vertices) {
    const Vector3d q = pose_b * v;
    for (const Vector3d& x : {s.s0, s.s1})
      if (const double dist = (q - x).norm(); dist > out.max_distance) out.max_distance = dist, out.far_a = x, out.far_b = q;
  }
}

// B before A swapped back: witnesses exchanged, direction negated.
void swap_sides(Proximity& out) {
  std::swap(out.point_a, out.point_b), std::swap(out.far_a, out.far_b);
  out.penetration_direction = -out.penetration_direction;
}

// The cores' answer with the radii ra, rb added to the fields `want` asks for (see the file's
// comment). Separated cores give the direction of their nearest points, rounding and all: a
// witness moves by its radius along a direction turned by up to (rounding of the points) /
// (the cores' distance).
void add_radii(double ra, double rb, Want want, Proximity& out) {
  const double r = ra + rb;
  if (has(want, Want::Verdict)) {
    Vector3d n = out.penetration_direction;
    if (!out.intersecting) {
      n = out.point_b - out.point_a;
      const double scale = n.cwiseAbs().maxCoeff();
      n = scale > 0 ? Vector3d(n / scale).normalized() : Vector3d::UnitZ();
      if (out.distance <= r) {
        out.intersecting = true;
        out.penetration_depth = r - out.distance, out.penetration_direction = n;
        out.distance = 0;
      } else {
        out.distance -= r;
      }
    } else {
      out.penetration_depth += r;
    }
    out.point_a += ra * n, out.point_b -= rb * n;
  }
  if (has(want, Want::MaxDistance)) {
    Vector3d w = out.far_b - out.far_a;
    const double len = w.norm();
    w = len > 0 ? Vector3d(w / len) : Vector3d::UnitZ();
    out.max_distance += r, out.far_a -= ra * w, out.far_b += rb * w;
  }
}

// The query of a rounded pair (or one with a point or segment core): the cores' answer, with
// the witnesses it needs to turn the radii, then the radii. A point or segment core keeps the
// face of the other core that held its last answer in the cache.
void rounded_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                       const Eigen::Isometry3d& pose_b, ProximityCache* cache, Proximity& out, Want want,
                       bool radii = true) {
  const Want core_want = has(want, Want::Verdict) ? want | Want::Witnesses : want;
  const bool seg_a = !data_of(a).has_faces(), seg_b = !data_of(b).has_faces();
  if (!seg_a && !seg_b) {
    detail::core_proximity(a, pose_a, b, pose_b, cache, out, core_want);
  } else {
    const bool swap = !seg_a;
    const ConvexShape &s = swap ? b : a, &t = swap ? a : b;
    const Eigen::Isometry3d &ps = swap ? pose_b : pose_a, &pt = swap ? pose_a : pose_b;
    int face = cache && cache->kind == detail::kCacheSegment ? cache->a[0] : -1;
    bool warm = false;
    if (has(want, Want::Verdict) && data_of(t).has_faces())
      warm = detail::segment_polytope(placed_segment(s, ps), t, pt, face, out);
    else if (has(want, Want::Verdict))
      detail::segment_pair(placed_segment(s, ps), placed_segment(t, pt), out), face = -1;
    if (has(want, Want::MaxDistance)) segment_farthest(s, ps, t, pt, out);
    if (swap) swap_sides(out);
    if (cache) {
      cache->kind = face >= 0 ? detail::kCacheSegment : 0u, cache->a[0] = face;
      ++(warm ? cache->warm : cache->cold);
    }
  }
  if (radii) add_radii(a.radius(), b.radius(), want, out);
}

// The shared checks of the posed entry points.
Status check_posed(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                   const Eigen::Isometry3d& pose_b) {
  if (a.empty() || b.empty()) return Status::TooFewPoints;
  for (const auto* pose : {&pose_a, &pose_b})
    if (const Status s = check_pose(*pose); s != Status::Ok) return s;
  return Status::Ok;
}

Status posed_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                       const Eigen::Isometry3d& pose_b, ProximityCache* cache, Proximity& out, Want want) {
  out = Proximity{};
  if (const Status s = check_posed(a, pose_a, b, pose_b); s != Status::Ok) return s;
  if (rounded(a, b))
    rounded_proximity(a, pose_a, b, pose_b, cache, out, want);
  else
    detail::core_proximity(a, pose_a, b, pose_b, cache, out, want);
  detail::keep_asked(want, out);
  return Status::Ok;
}

// The cores' patch within the margin plus the radii, each point moved from A's core plane to
// A's surface, the depth grown by the radii. A point or segment core: from the cores' answer
// (its supporting set is the point, an end, or the segment level with the other's).
Status posed_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                   const Eigen::Isometry3d& pose_b, double margin, ProximityCache* cache, ContactPatch& out) {
  out.size = 0, out.normal.setZero(), out.depth = 0, out.feature_a = out.feature_b = {};
  if (const Status s = check_posed(a, pose_a, b, pose_b); s != Status::Ok) return s;
  if (!(margin >= 0)) return Status::InvalidArgument;
  const double r = a.radius() + b.radius();
  Status s;
  if (data_of(a).has_faces() && data_of(b).has_faces()) {
    s = detail::core_patch(a, pose_a, b, pose_b, margin + r, cache, out);
  } else {
    Proximity cores;
    rounded_proximity(a, pose_a, b, pose_b, cache, cores, Want::Witnesses, false);
    s = detail::answer_patch(a, pose_a, b, pose_b, cores, margin + r, out);
  }
  if (s != Status::Ok || r == 0) return s;
  out.depth += r;
  for (int k = 0; k < out.size; ++k) out.points[k] += a.radius() * out.normal;
  return Status::Ok;
}

}  // namespace

void detail::cores_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                             const Eigen::Isometry3d& pose_b, Proximity& out) {
  out = Proximity{};
  if (rounded(a, b))
    rounded_proximity(a, pose_a, b, pose_b, nullptr, out, Want::Witnesses, false);
  else
    detail::core_proximity(a, pose_a, b, pose_b, nullptr, out, Want::Witnesses);
}

Status detail::cores_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                           const Eigen::Isometry3d& pose_b, double margin, ContactPatch& out) {
  if (data_of(a).has_faces() && data_of(b).has_faces()) return detail::core_patch(a, pose_a, b, pose_b, margin, nullptr, out);
  Proximity cores;
  rounded_proximity(a, pose_a, b, pose_b, nullptr, cores, Want::Witnesses, false);
  return detail::answer_patch(a, pose_a, b, pose_b, cores, margin, out);
}

Status proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                 const Eigen::Isometry3d& pose_b, Proximity& out, Want want) {
  return posed_proximity(a, pose_a, b, pose_b, nullptr, out, want);
}

Status proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                 const Eigen::Isometry3d& pose_b, ProximityCache& cache, Proximity& out, Want want) {
  return posed_proximity(a, pose_a, b, pose_b, &cache, out, want);
}

Status contact_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, double margin, ContactPatch& out) {
  return posed_patch(a, pose_a, b, pose_b, margin, nullptr, out);
}

Status contact_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, double margin, ProximityCache& cache, ContactPatch& out) {
  return posed_patch(a, pose_a, b, pose_b, margin, &cache, out);
}

}  // namespace minksum
