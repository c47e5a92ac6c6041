// Proximity queries on two polytopes or posed shapes without building M = A (-) B: prepared
// boxes and triangles in their own form, else GJK (gjk.hpp) under a certificate
// (certificates.hpp, epa.hpp, faces.hpp) or the exhaustive search (search.hpp), over the shape
// views of views.hpp; the coherent path through the cache; the contact patch. (Box pairs are
// box_query.cpp's, reading a built M built_sum.cpp's.)
#include <minksum/query.hpp>

#include <minksum/kernels.hpp>

#include "core/scale.hpp"
#include "geometry/closest.hpp"
#include "geometry/rigid.hpp"
#include "query/box_query.hpp"
#include "query/cache_kinds.hpp"
#include "query/certificates.hpp"
#include "query/core_query.hpp"
#include "query/epa.hpp"
#include "query/faces.hpp"
#include "query/gjk.hpp"
#include "query/patch.hpp"
#include "query/search.hpp"
#include "query/triangle_pairs.hpp"
#include "query/views.hpp"
#include "query/wide_scan.hpp"
#include "shape/shape_data.hpp"
#include "simd/box_pair_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

namespace {

using detail::kCacheBoxBox;
using detail::kCacheConvex;
// ProximityCache::active of a convex cache: its pairs span M's facet of the last depth.
constexpr unsigned kDepthFacet = 1;
// ProximityCache::active of a convex cache: bit 1 set, the answer's normal is a face normal,
// of B if bit 2 is set (else of A), the face in the bits above.
constexpr unsigned kFaceNormal = 2;

}  // namespace

[[gnu::noinline]] void detail::wide_scan(const double* x, const double* y, const double* z, int n, double nx, double ny,
                                         double nz, double& top, int& arg) {
  support_push(x, y, z, n, &nx, &ny, &nz, 1, &top, &arg);
}

namespace {

// The farthest pair: every vertex pair, squared lengths scaled by k (a power of two).
template <class A, class B>
void farthest_pair(const A& a, const B& b, double k, Proximity& out) {
  double far2 = -1;
  for (int i = 0; i < a.size(); ++i)
    for (int j = 0; j < b.size(); ++j)
      if (const double d2 = (k * (a.vertex(i) - b.vertex(j))).squaredNorm(); d2 > far2)
        far2 = d2, out.far_a = a.vertex(i), out.far_b = b.vertex(j);
  out.max_distance = length(out.far_a - out.far_b);
}

// The barycentric weights of the origin in the tetrahedron w[0..4) (scaled by k); false if it
// is flat to rounding.
bool origin_weights(const Vector3d (&w)[4], double (&l)[4]) {
  const Vector3d e1 = w[1] - w[0], e2 = w[2] - w[0], e3 = w[3] - w[0];
  const double det = e1.dot(e2.cross(e3));
  if (!(std::abs(det) > 1e-12 * e1.norm() * e2.norm() * e3.norm())) return false;
  l[1] = -w[0].dot(e2.cross(e3)) / det, l[2] = e1.dot(-w[0].cross(e3)) / det, l[3] = e1.dot(e2.cross(-w[0])) / det;
  l[0] = 1 - l[1] - l[2] - l[3];
  for (double x : l)
    if (!(x >= -1e-9)) return false;
  return true;
}

// GJK's features proven (see the certificates): the distance (3 pairs), the depth (a
// tetrahedron around the origin), or touching (either); then the witnesses from the contact
// frame, and the features kept for the next query. False if no certificate holds. Apart, the
// features' nearest pair is a closest pair already: the contact frame's (the point of the
// level sets' overlap, which slides with the shapes) only where the caller asks for the patch.
template <class A, class B>
bool certified(const A& a, const B& b, int found, const int (&fa)[4], const int (&fb)[4], const double (&weight)[3],
               const Tolerances& t, Want want, Proximity& out, Features* f) {
  if (found != 3 && found != 4) return false;
  Vector3d s[4], u[4];
  for (int j = 0; j < found; ++j) s[j] = a.vertex(fa[j]), u[j] = b.vertex(fb[j]);
  Contact c;
  Vector3d p, q;
  bool ok = false, touching = false;  // (touching: certified_touching has set the patch's witnesses)
  const auto depth = [&](bool proven) {
    if (proven) c = heights(a, b, out.penetration_direction, t.tau);
    return proven;
  };
  if (found == 3) {
    double d;
    ok = certified_distance(a, b, s, u, weight, t.slack, t.touching, t.tau, p, q, d, out, c) ||
         (touching = certified_touching(a, b, p, q, s, u, 3, t.touching, t.tau, t.margin, out, c)) ||
         (d <= t.touching + t.slack && depth(depth_from_faces(a, b, 3, fa, fb, t, out, f)));
  } else {
    // Deeper than `touching`, the tetrahedron proves the depth; else, where the origin lies
    // in it, touching is tried before the tetrahedron's faces (at touching those cannot prove
    // a depth: every face of the expanding polytope must be farther than `touching`).
    Vector3d w[4];
    double l[4];
    for (int j = 0; j < 4; ++j) w[j] = t.k * (s[j] - u[j]);
    ok = depth(certified_depth(a, b, fa, fb, t.slack, t.touching, out, f));
    if (!ok && origin_weights(w, l)) {
      p = l[0] * s[0] + l[1] * s[1] + l[2] * s[2] + l[3] * s[3];
      q = l[0] * u[0] + l[1] * u[1] + l[2] * u[2] + l[3] * u[3];
      ok = touching = certified_touching(a, b, p, q, s, u, 4, t.touching, t.tau, t.margin, out, c);
    }
    ok = ok || depth(depth_from_faces(a, b, 4, fa, fb, t, out, f));
  }
  if (!ok) return false;
  // Apart, B's witness is A's moved along n by the planes' gap bottom - top (within the slack
  // of d), and the answer is the distance they realise (at coordinates of 1e86 the slack is
  // 1e-4 of a distance of 1e74). A's is GJK's point, or with the patch the point of the level
  // sets' overlap (the two levels' distances then differ by the rounding of the points).
  if (!out.intersecting) {
    if (!has(want, Want::Patch) || !contact_witnesses(a, b, c, t.tau, out.point_a, out.point_b))
      out.point_b = out.point_a + (c.bottom - c.top) * c.n;
    out.distance = length(out.point_b - out.point_a);
  } else if (!touching || c.a_single || c.b_single) {
    contact_witnesses(a, b, c, t.tau, out.point_a, out.point_b);
  }
  if (f) f->normal = c.n;
  if (f && !f->depth) {
    std::copy(fa, fa + 3, f->a), std::copy(fb, fb + 3, f->b);
    f->valid = true;
  }
  return true;
}

// The cold query's verdict, distance or depth and witnesses: GJK's features under a
// certificate, else the exhaustive search.
template <class A, class B>
void proven_proximity(const A& a, const B& b, const Tolerances& t, Proximity& out, Want want, Features* features) {
  int fa[4], fb[4];
  double weight[3];
  const int first = 0;
  Gjk<A, B> gjk(a, b, t.k, &first, &first, 1);
  if (!gjk.run(kFaceFirst)) {
    Features f;
    if (face_first(a, b, gjk.nearest(), t, want, out, f)) {
      if (features) *features = f;
      return;
    }
    out = Proximity{};
    gjk.run();
  }
  int found = gjk.features(fa, fb, weight);
  if (certified(a, b, found, fa, fb, weight, t, want, out, features)) return;
  // Once more from the supports along the line between the first vertices: rounding stalls GJK
  // on needles and slivers from one start and not from another (a triangle 1e10 long, where
  // the search below also misjudges).
  double unused;
  const Vector3d d = b.vertex(0) - a.vertex(0);
  const int sa = highest(a, d, unused), sb = highest(b, Vector3d(-d), unused);
  found = gjk_features(a, b, t.k, &sa, &sb, 1, fa, fb, weight);
  if (certified(a, b, found, fa, fb, weight, t, want, out, features)) return;
  if (features && (found == 3 || found == 4)) {
    std::copy(fa, fa + 3, features->a), std::copy(fb, fb + 3, features->b);
    features->valid = true;
  }
  searched_proximity(a, b, found, t, out);
}

// Exact proximity of two shapes: GJK's answer where a certificate proves it, else the
// exhaustive search; the farthest pair where asked.
template <class A, class B>
void exact_proximity(const A& a, const B& b, Proximity& out, Want want, Features* features = nullptr) {
  out = Proximity{};
  const Tolerances t = tolerances(a, b);
  if (has(want, Want::Verdict)) proven_proximity(a, b, t, out, want, features);
  if (has(want, Want::MaxDistance)) farthest_pair(a, b, t.k, out);
}

// The coherent path (ProximityCache): GJK from the last answer's support pairs, which along a
// smooth motion ends after one or two supports, and the cold query's certificates, so that
// the answer is the cold one's to their slack. Anything else (a stale or foreign cache, a
// badly scaled pose, no certificate) returns false, and the caller answers cold.
// The overlapping case from the last depth: its facet of M (three support pairs) and M's
// support point on the other side of the origin make a tetrahedron around it, from which the
// expanding polytope's certificate usually holds at once (the facet is still M's nearest).
template <class A, class B>
bool warm_depth(const A& a, const B& b, const ProximityCache& cache, const Tolerances& t, Want want, Proximity& out,
                Features& f) {
  Vector3d w[3];
  for (int j = 0; j < 3; ++j) w[j] = a.vertex(cache.a[j]) - b.vertex(cache.b[j]);
  Vector3d n = (w[1] - w[0]).cross(w[2] - w[0]);
  if (n.dot(w[0]) < 0) n = -n;  // towards the facet, away from the origin
  double unused;
  const int ka = highest(a, -n, unused), kb = highest(b, n, unused);
  int ta[4] = {cache.a[0], cache.a[1], cache.a[2], ka}, tb[4] = {cache.b[0], cache.b[1], cache.b[2], kb};
  const double none[3] = {0, 0, 0};  // (a tetrahedron: no nearest point)
  if (certified(a, b, 4, ta, tb, none, t, want, out, &f)) return true;
  out = Proximity{}, f = Features{};
  return false;
}

// (Flattened: see MINKSUM_FLATTEN.)
template <class A, class B>
MINKSUM_FLATTEN bool warm_proximity(const A& a, const B& b, const ProximityCache& cache, Proximity& out, Want want,
                                    Features& f) {
  if (cache.kind != kCacheConvex || !has(want, Want::Verdict)) return false;
  for (int j = 0; j < 3; ++j)
    if (cache.a[j] < 0 || cache.a[j] >= a.size() || cache.b[j] < 0 || cache.b[j] >= b.size()) return false;
  const Tolerances t = tolerances(a, b);
  if (!(t.reach > 0 && t.reach <= kMaxCoordinate)) return false;
  out = Proximity{};
  bool ok = (cache.active & kFaceNormal) &&
            face_probe(a, b, int(cache.active >> 3), (cache.active & 4) != 0, t, want, out, f);
  ok = ok || (cache.active == kDepthFacet && warm_depth(a, b, cache, t, want, out, f));
  if (!ok) {
    int fa[4], fb[4];
    double weight[3];
    const int found = gjk_features(a, b, t.k, cache.a, cache.b, 3, fa, fb, weight);
    ok = certified(a, b, found, fa, fb, weight, t, want, out, &f);
  }
  // Apart or overlapping by less than 1e-9 of the coordinates (touching included), the verdict
  // rests on the touching tolerance, which the cold query may reach from other features (at
  // coordinates of 1e86: 1e74 apart cold and touching warm, and the reverse; and a touching
  // face probe against a search that found them apart by just over touching): the cold query
  // answers.
  const double clear = 1e-9 * t.reach;
  ok = ok && (out.intersecting ? out.penetration_depth > clear : out.distance > clear);
  if (!ok) return out = Proximity{}, f = Features{}, false;
  if (has(want, Want::MaxDistance)) farthest_pair(a, b, t.k, out);
  return true;
}

// A query through the cache: warm if it proves, else cold; the cache keeps the features (and
// `features` gets them, where asked).
template <class A, class B>
void cached_proximity(const A& a, const B& b, ProximityCache& cache, Proximity& out, Want want,
                      Features* features = nullptr) {
  Features f;
  const bool warm = warm_proximity(a, b, cache, out, want, f);
  if (!warm) exact_proximity(a, b, out, want, &f);
  // (An answer the coherent path would leave to the cold one: the next query starts cold, so
  // that it is never slower than cold.)
  const double clear = 1e-9 * std::max(a.reach(), b.reach());
  if (!(out.intersecting ? out.penetration_depth > clear : out.distance > clear)) f.valid = false;
  // Which face the proof's normal is, for the next query's probe: only for an answer kept
  // (a touching one is not, and costs no face search).
  if (f.valid && !f.depth && f.face < 0 && f.normal.squaredNorm() > 0) face_normal_of(a, b, f.normal, f);
  ++(warm ? cache.warm : cache.cold);
  cache.searched += out.searched;
  cache.kind = f.valid ? kCacheConvex : 0u;
  cache.active = f.depth       ? kDepthFacet
                 : f.face >= 0 ? kFaceNormal | unsigned(f.face_of_b) << 2 | unsigned(f.face) << 3
                               : 0u;
  std::copy(f.a, f.a + 3, cache.a), std::copy(f.b, f.b + 3, cache.b);
  if (features) *features = f;
}

// A box shape's box placed by a pose.
Box placed_box(const detail::ShapeData& d, const Eigen::Isometry3d& pose) {
  Box x = d.box;
  x.center = pose * d.box.center, x.rotation = pose.linear() * d.box.rotation;
  return x;
}

// Shapes built from boxes and triangles answer in their own form, placed by their poses: the
// box-box, box-triangle and triangle-triangle paths (and their caches), B before A swapped
// back (witnesses exchanged, direction negated). Two boxes are not checked again (their
// preparation and the poses were). False if either is general (or a placed box or triangle
// fails its check by the rounding of the pose): the general path answers.
bool own_form(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
              const Eigen::Isometry3d& pose_b, ProximityCache* cache, Proximity& out, Want want) {
  using Kind = detail::ShapeData::Kind;
  const detail::ShapeData &da = *detail::ShapeAccess::data(a), &db = *detail::ShapeAccess::data(b);
  if (da.kind == Kind::General || db.kind == Kind::General) return false;
  const auto triangle = [](const detail::ShapeData& d, const Eigen::Isometry3d& pose) {
    return Triangle{pose * d.triangle.a, pose * d.triangle.b, pose * d.triangle.c};
  };
  Status s = Status::Ok;
  if (da.kind == Kind::Box && db.kind == Kind::Box) {
    detail::box_answer(placed_box(da, pose_a), placed_box(db, pose_b), cache, out, want);
  } else if (da.kind == Kind::Triangle && db.kind == Kind::Triangle) {
    const Triangle x = triangle(da, pose_a), y = triangle(db, pose_b);
    if (!cache) {
      s = proximity(x, y, out, want);
    } else if ((s = check_triangle(x)) == Status::Ok && (s = check_triangle(y)) == Status::Ok) {
      cached_proximity(shape_of(x), shape_of(y), *cache, out, want);
    }
  } else {
    const bool swap = da.kind == Kind::Triangle;
    const Box x = swap ? placed_box(db, pose_b) : placed_box(da, pose_a);
    const Triangle y = swap ? triangle(da, pose_a) : triangle(db, pose_b);
    s = cache ? proximity(x, y, *cache, out, want) : proximity(x, y, out, want);
    if (swap) {
      std::swap(out.point_a, out.point_b), std::swap(out.far_a, out.far_b);
      out.penetration_direction = -out.penetration_direction;
    }
  }
  if (s == Status::Ok) return true;
  out = Proximity{};
  return false;
}

// The vertices of s within tau of its level (sign as in level_set) as a convex polygon seen
// along n, counter-clockwise: the supporting set where it is no face, edge or vertex (faces
// planar only to a tolerance). Andrew's monotone chain (Andrew, "Another efficient algorithm
// for convex hulls in two dimensions", 1979). False for kPatch vertices or more.
template <class S>
bool level_hull(const S& s, const Vector3d& n, double level, double sign, double tau, const Vector3d& u,
                const Vector3d& w, Patch& out) {
  Eigen::Vector2d q[kPatch];
  int m = 0;
  for (int k = 0; k < s.size(); ++k) {
    const Vector3d x = s.vertex(k);
    if (!(sign * (n.dot(x) - level) >= -tau)) continue;
    if (m == kPatch - 1) return false;
    q[m++] = Eigen::Vector2d(u.dot(x), w.dot(x));
  }
  std::sort(q, q + m, [](const Eigen::Vector2d& x, const Eigen::Vector2d& y) {
    return x.x() < y.x() || (x.x() == y.x() && x.y() < y.y());
  });
  // The lower hull left to right, then the upper right to left (m + 1 points at most).
  out.size = 0;
  const auto push = [&](const Eigen::Vector2d& x, int floor) {
    while (out.size >= floor + 2 && cross2(out.p[out.size - 1] - out.p[out.size - 2], x - out.p[out.size - 2]) <= 0)
      --out.size;
    out.p[out.size++] = x;
  };
  for (int k = 0; k < m; ++k) push(q[k], 0);
  const int lower = out.size - 1;
  for (int k = m - 2; k >= 0; --k) push(q[k], lower);
  if (out.size > 1) --out.size;  // the first point again
  settle(out, tau);
  return out.size > 0;
}

// A level set's feature as the public kind.
ContactPatch::Feature feature_of(const LevelFeature& f) {
  using Kind = ContactPatch::Feature::Kind;
  if (f.face >= 0) return {Kind::Face, {f.face, -1}};
  if (f.vertex[1] >= 0) return {Kind::Edge, {f.vertex[0], f.vertex[1]}};
  if (f.vertex[0] >= 0) return {Kind::Vertex, {f.vertex[0], -1}};
  return {};
}

// The contact patch of an exact answer p (see contact_patch): along its normal n, A's top set
// and B's bottom set (level_set, or level_hull where neither a face nor an edge is) seen along
// n, and their overlap, clipped in O(n_A + n_B) (Sutherland and Hodgman, "Reentrant polygon
// clipping", 1974), lifted onto A's supporting plane.
template <class A, class B>
Status patch_of(const A& a, const B& b, const Proximity& p, const Features& f, double margin, ContactPatch& out) {
  const Tolerances t = tolerances(a, b);
  // The normal of the planes that proved the answer: the witnesses' difference is turned by
  // rounding / distance (1e-7 rad at 1e-9 apart). Where the search answered: overlapping, its
  // unit direction; apart, the witnesses' (the distance is more than `touching`).
  const Vector3d n = f.normal.squaredNorm() > 0 ? f.normal
                     : p.intersecting           ? p.penetration_direction
                                                : Vector3d((p.point_b - p.point_a).normalized());
  out.normal = n;
  out.depth = p.intersecting ? p.penetration_depth : -p.distance;
  if (!p.intersecting && !(p.distance <= margin)) return Status::Ok;
  const Contact c = heights(a, b, n, t.tau);
  const Vector3d u = n.unitOrthogonal(), w = n.cross(u);
  Patch P, Q, O;
  LevelFeature fa, fb;
  // (Where level_set gives up, it has named two vertices already: the hull is no feature.)
  if (!level_set(a, n, c.top, 1.0, t.tau, u, w, P, &fa) && (fa = {}, !level_hull(a, n, c.top, 1.0, t.tau, u, w, P)))
    return Status::CapacityExceeded;
  if (!level_set(b, n, c.bottom, -1.0, t.tau, u, w, Q, &fb) &&
      (fb = {}, !level_hull(b, n, c.bottom, -1.0, t.tau, u, w, Q)))
    return Status::CapacityExceeded;
  if (P.size + Q.size > kPatch) return Status::CapacityExceeded;  // (the overlap has at most that many)
  out.feature_a = feature_of(fa), out.feature_b = feature_of(fb);
  detail::overlap_of_sets(P, Q, t.tau, O);
  // Where rounding has the sets miss by more than tau (they met in the certificate), the
  // answer's witness: a one-point patch.
  if (O.size == 0) O.p[0] = Eigen::Vector2d(u.dot(p.point_a), w.dot(p.point_a)), O.size = 1;
  detail::tidy(O, t.tau);
  out.size = O.size;
  for (int k = 0; k < O.size; ++k) out.points[k] = O.p[k].x() * u + O.p[k].y() * w + c.top * n;
  return Status::Ok;
}

}  // namespace

Status proximity(const ConvexPolytope& a, const ConvexPolytope& b, Proximity& out, Want want) {
  out = Proximity{};
  if (a.vertices.empty() || b.vertices.empty() || a.faces.empty() || b.faces.empty()) return Status::TooFewPoints;
  exact_proximity(PolytopeShape{a}, PolytopeShape{b}, out, want);
  detail::keep_asked(want, out);
  return Status::Ok;
}

void detail::core_proximity(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                            const Eigen::Isometry3d& pose_b, ProximityCache* cache, Proximity& out, Want want) {
  if (own_form(a, pose_a, b, pose_b, cache, out, want)) return;
  if (cache)
    cached_proximity(posed(a, pose_a), posed(b, pose_b), *cache, out, want);
  else
    exact_proximity(posed(a, pose_a), posed(b, pose_b), out, want);
}

Status proximity(const Box& a, const Triangle& b, Proximity& out, Want want) {
  out = Proximity{};
  if (const Status s = check_box(a); s != Status::Ok) return s;
  if (const Status s = check_triangle(b); s != Status::Ok) return s;
  exact_proximity(shape_of(a), shape_of(b), out, want);
  detail::keep_asked(want, out);
  return Status::Ok;
}

Status proximity(const Box& a, const Triangle& b, ProximityCache& cache, Proximity& out, Want want) {
  out = Proximity{};
  if (const Status s = check_box(a); s != Status::Ok) return s;
  if (const Status s = check_triangle(b); s != Status::Ok) return s;
  cached_proximity(shape_of(a), shape_of(b), cache, out, want);
  detail::keep_asked(want, out);
  return Status::Ok;
}

Status proximity(const Triangle& a, const Triangle& b, Proximity& out, Want want) {
  out = Proximity{};
  for (const Triangle* t : {&a, &b})
    if (const Status s = check_triangle(*t); s != Status::Ok) return s;
  exact_proximity(shape_of(a), shape_of(b), out, want);
  detail::keep_asked(want, out);
  return Status::Ok;
}

namespace {

// Box and triangle shapes: the patch from their separating axes (15 for two boxes, 13 for a box
// and a triangle, B before A swapped back), where those decide; farther apart than the
// margin, no patch and the pair's exact distance. False where the general path answers
// (also where a placed box fails check_box by the rounding of its rotation). They need no cache.
bool own_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
               const Eigen::Isometry3d& pose_b, double margin, ContactPatch& out) {
  using Kind = detail::ShapeData::Kind;
  using detail::BoxPatch;
  const detail::ShapeData &da = *detail::ShapeAccess::data(a), &db = *detail::ShapeAccess::data(b);
  const bool boxes = da.kind == Kind::Box && db.kind == Kind::Box;
  const bool swap = da.kind == Kind::Triangle && db.kind == Kind::Box;
  if (!boxes && !swap && !(da.kind == Kind::Box && db.kind == Kind::Triangle)) return false;
  // (A placed box is not checked again: its preparation and the pose were, as in box_answer.)
  const Box x = swap ? placed_box(db, pose_b) : placed_box(da, pose_a);
  BoxPatch decided;
  Proximity p;
  if (boxes) {
    const Box y = placed_box(db, pose_b);
    decided = detail::box_pair_patch(x, y, margin, out);
    if (decided == BoxPatch::Apart) detail::box_answer(x, y, nullptr, p, Want::Witnesses);
  } else {
    const detail::ShapeData& dt = swap ? da : db;
    const Eigen::Isometry3d& pose = swap ? pose_a : pose_b;
    const Triangle y{pose * dt.triangle.a, pose * dt.triangle.b, pose * dt.triangle.c};
    if (check_triangle(y) != Status::Ok) return false;
    decided = detail::box_triangle_patch(x, y, margin, out);
    if (decided == BoxPatch::Apart && proximity(x, y, p) != Status::Ok) return false;
  }
  // Apart by the axes but within the margin by the exact query (a touching pair whose axis
  // rounds to a gap): the general path, which follows the exact verdict.
  if (decided == BoxPatch::Apart && (p.intersecting || p.distance <= margin)) return false;
  if (decided == BoxPatch::Undecided) return false;
  if (decided == BoxPatch::Apart) {  // no patch; the normal from the box's witness to the other's
    out.size = 0, out.depth = -p.distance, out.normal = (p.point_b - p.point_a).normalized();
    out.feature_a = out.feature_b = {};
  }
  if (swap) {  // the triangle is A: its plane, the normal turned, the order reversed
    out.normal = -out.normal;
    for (int k = 0; k < out.size; ++k) out.points[k] += out.depth * out.normal;
    std::reverse(out.points, out.points + out.size);
    std::swap(out.feature_a, out.feature_b);
  }
  return true;
}

}  // namespace

Status detail::answer_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                            const Eigen::Isometry3d& pose_b, const Proximity& cores, double margin, ContactPatch& out) {
  out.size = 0, out.normal.setZero(), out.depth = 0, out.feature_a = out.feature_b = {};
  const Status s = patch_of(posed(a, pose_a), posed(b, pose_b), cores, Features{}, margin, out);
  if (s != Status::Ok) out.size = 0, out.feature_a = out.feature_b = {};
  return s;
}

Status detail::core_patch(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                          const Eigen::Isometry3d& pose_b, double margin, ProximityCache* cache,
                          ContactPatch& out) {
  out.size = 0, out.normal.setZero(), out.depth = 0, out.feature_a = out.feature_b = {};
  if (own_patch(a, pose_a, b, pose_b, margin, out)) return Status::Ok;
  out.size = 0, out.normal.setZero(), out.depth = 0, out.feature_a = out.feature_b = {};
  const PosedShape pa = posed(a, pose_a), pb = posed(b, pose_b);
  Proximity p;
  Features f;
  if (cache)
    cached_proximity(pa, pb, *cache, p, Want::Patch, &f);
  else
    exact_proximity(pa, pb, p, Want::Patch, &f);
  const Status s = patch_of(pa, pb, p, f, margin, out);
  if (s != Status::Ok) out.size = 0, out.feature_a = out.feature_b = {};
  return s;
}

}  // namespace minksum
