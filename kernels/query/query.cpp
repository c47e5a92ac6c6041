// Proximity queries on two polytopes or posed shapes without building M = A (-) B: boxes and
// triangles in their own form, else GJK under a certificate, EPA and the exhaustive search
// (reading a built M is built_sum.cpp's).
#include <minksum/query.hpp>

#include <minksum/kernels.hpp>

#include "core/scale.hpp"
#include "geometry/closest.hpp"
#include "geometry/rigid.hpp"
#include "simd/box_pair_data.hpp"
#include "query/box_query.hpp"
#include "query/cache_kinds.hpp"
#include "query/core_query.hpp"
#include "query/patch.hpp"
#include "shape/shape_data.hpp"
#include "query/triangle_pairs.hpp"
#include "query/wide_scan.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

// Flattening the warm query and the depth certificate keeps Eigen's 3-vector operations
// inline in the release build (GCC leaves them as calls in this large file). Under a
// sanitizer the instrumented, fully inlined bodies take the compiler over ten minutes, and
// speed does not matter there: no flattening.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define MINKSUM_FLATTEN
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define MINKSUM_FLATTEN
#endif
#endif
#ifndef MINKSUM_FLATTEN
#define MINKSUM_FLATTEN [[gnu::flatten]]
#endif

namespace minksum {

using detail::after;
using detail::area2;
using detail::cross2;
using detail::kPatch;
using detail::meets;
using detail::Patch;
using detail::patch_point;
using detail::settle;
using Eigen::Vector3d;

namespace {

using detail::kCacheBoxBox;
using detail::kCacheConvex;
// ProximityCache::active of a convex cache: its pairs span M's facet of the last depth.
constexpr unsigned kDepthFacet = 1;
// ProximityCache::active of a convex cache: bit 1 set, the answer's normal is a face normal,
// of B if bit 2 is set (else of A), the face in the bits above.
constexpr unsigned kFaceNormal = 2;

void box_patch(const Box& a, const Box& b, Proximity& out);

// Both box queries on boxes already checked (a prepared box placed by a checked pose is: its
// rotation is the product of two checked ones), through the active set of `cache` if given;
// the patch's witnesses where asked.
void box_answer(const Box& a, const Box& b, ProximityCache* cache, Proximity& out, Want want) {
  unsigned active = cache && cache->kind == kCacheBoxBox ? cache->active : 0u;
  bool warm = false;
  detail::box_query(a, b, out, want, active, warm);
  if (has(want, Want::Patch)) box_patch(a, b, out);
  if (!cache) return;
  cache->kind = kCacheBoxBox, cache->active = active;
  ++(warm ? cache->warm : cache->cold);
}

// check_box of both.
Status check_boxes(const Box& a, const Box& b) {
  const Status s = check_box(a);
  return s != Status::Ok ? s : check_box(b);
}

}  // namespace

Status proximity(const Box& a, const Box& b, Proximity& out, Want want) {
  const Status s = check_boxes(a, b);
  if (s != Status::Ok) return out = Proximity{}, s;
  box_answer(a, b, nullptr, out, want);
  return Status::Ok;
}

Status proximity(const Box& a, const Box& b, ProximityCache& cache, Proximity& out, Want want) {
  const Status s = check_boxes(a, b);
  if (s != Status::Ok) return out = Proximity{}, cache.kind = kCacheBoxBox, cache.active = 0, ++cache.cold, s;
  box_answer(a, b, &cache, out, want);
  return Status::Ok;
}

namespace {

// Exact proximity without building A (-) B, so without allocation (a haptics tick may call
// it). A shape is read through a view: its vertices, its faces (a vertex loop, the outward
// normal and offset; a flat shape has one face and no inside), and its edge directions.

// The vertex of s highest along n, and its height n . x (the support); the first of ties.
template <class S>
int highest(const S& s, const Vector3d& n, double& value) {
  int best = 0;
  value = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < s.size(); ++k)
    if (const double x = n.dot(s.vertex(k)); x > value) value = x, best = k;
  return best;
}

// The largest |coordinate| of s's vertices.
template <class S>
double largest_coordinate(const S& s) {
  double m = 0;
  for (int k = 0; k < s.size(); ++k) m = std::max(m, s.vertex(k).cwiseAbs().maxCoeff());
  return m;
}

// A box or a triangle in fixed arrays.
struct SmallShape {
  Vector3d v[8];
  int nv = 0;
  int face[6][4];
  int face_size = 0, nf = 0;
  Vector3d normal[6];
  double offset[6];
  Vector3d edge[3];  // unit directions: a box's axes, a triangle's edges
  int ne = 0;
  bool solid = false;
  int size() const { return nv; }
  const Vector3d& vertex(int k) const { return v[k]; }
  int faces() const { return nf; }
  int loop_size(int) const { return face_size; }
  const Vector3d& loop_vertex(int f, int k) const { return v[face[f][k]]; }
  const Vector3d& face_normal(int f) const { return normal[f]; }
  double face_offset(int f) const { return offset[f]; }
  int edges() const { return ne; }
  Vector3d edge_direction(int k) const { return edge[k]; }
  bool arc(int, Vector3d&, Vector3d&, Vector3d&) const { return false; }  // directions only: no Gauss map
  double reach() const { return largest_coordinate(*this); }
  // The body frame (see PosedShape): the world frame here.
  const Vector3d& to_body(const Vector3d& d) const { return d; }
  const Vector3d& body_point(const Vector3d& x) const { return x; }
  double shift(const Vector3d&) const { return 0; }
  const Vector3d& body_vertex(int k) const { return v[k]; }
  const Vector3d& body_loop_vertex(int f, int k) const { return v[face[f][k]]; }
  const Vector3d& body_normal(int f) const { return normal[f]; }
  double body_offset(int f) const { return offset[f]; }
};

SmallShape shape_of(const Box& b) {
  SmallShape s;
  s.nv = 8;
  for (int k = 0; k < 8; ++k) s.v[k] = box_corner(b, k);
  // The face of axis a on side `side` holds the corners whose bit a is `side`; the other two
  // bits run around it.
  for (int a = 0, f = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side, ++f) {
      const int u = 1 << ((a + 1) % 3), w = 1 << ((a + 2) % 3), base = side << a;
      const int loop[4] = {base, base | u, base | u | w, base | w};
      for (int k = 0; k < 4; ++k) s.face[f][k] = loop[k];
      s.normal[f] = (side ? 1.0 : -1.0) * b.rotation.col(a);
      s.offset[f] = s.normal[f].dot(s.v[base]);
    }
  s.nf = 6, s.face_size = 4;
  for (int a = 0; a < 3; ++a) s.edge[a] = b.rotation.col(a);
  s.ne = 3;
  s.solid = true;
  return s;
}

SmallShape shape_of(const Triangle& t) {
  SmallShape s;
  s.v[0] = t.a, s.v[1] = t.b, s.v[2] = t.c;
  s.nv = 3;
  for (int k = 0; k < 3; ++k) s.face[0][k] = k;
  s.nf = 1, s.face_size = 3;
  // Unit edges first: products of raw coordinates up to 1e100 would overflow.
  s.edge[0] = (t.b - t.a).stableNormalized(), s.edge[1] = (t.c - t.b).stableNormalized();
  s.edge[2] = (t.a - t.c).stableNormalized();
  s.normal[0] = s.edge[0].cross(s.edge[1]).stableNormalized();
  s.offset[0] = s.normal[0].dot(t.a);
  s.ne = 3;
  return s;
}

// A convex polytope, read in place.
struct PolytopeShape {
  const ConvexPolytope& p;
  bool solid = !p.flat;
  int size() const { return int(p.vertices.size()); }
  const Vector3d& vertex(int k) const { return p.vertices[k]; }
  int faces() const { return p.flat ? 1 : int(p.faces.size()); }  // a flat one: one side
  int loop_size(int f) const { return int(p.faces[f].loop.size()); }
  const Vector3d& loop_vertex(int f, int k) const { return p.vertices[p.faces[f].loop[k]]; }
  const Vector3d& face_normal(int f) const { return p.faces[f].normal; }
  double face_offset(int f) const { return p.faces[f].offset; }
  int edges() const { return int(p.edges.size()); }
  Vector3d edge_direction(int k) const {
    return (p.vertices[p.edges[k].v1] - p.vertices[p.edges[k].v0]).stableNormalized();
  }
  // Edge k's arc in the Gauss map: the normals of its two faces (a flat one has none), and a
  // point of the edge.
  bool arc(int k, Vector3d& n0, Vector3d& n1, Vector3d& on) const {
    if (p.flat) return false;
    n0 = p.faces[p.edges[k].left].normal, n1 = p.faces[p.edges[k].right].normal;
    on = p.vertices[p.edges[k].v0];
    return true;
  }
  double reach() const { return largest_coordinate(*this); }
  // The body frame (see PosedShape): the world frame here.
  const Vector3d& to_body(const Vector3d& d) const { return d; }
  const Vector3d& body_point(const Vector3d& x) const { return x; }
  double shift(const Vector3d&) const { return 0; }
  const Vector3d& body_vertex(int k) const { return p.vertices[k]; }
  const Vector3d& body_loop_vertex(int f, int k) const { return p.vertices[p.faces[f].loop[k]]; }
  const Vector3d& body_normal(int f) const { return p.faces[f].normal; }
  double body_offset(int f) const { return p.faces[f].offset; }
};

// A convex polytope in its body frame, read in place and placed by a rigid pose on the fly
// (x' = R x + t; normals and directions turned by R): nothing is stored per pose.
struct PosedShape {
  const ConvexPolytope& p;
  const detail::Rigid pose;
  const bool solid = !p.flat;
  int size() const { return int(p.vertices.size()); }
  Vector3d vertex(int k) const { return pose.point(p.vertices[k]); }
  int faces() const { return p.flat ? 1 : int(p.faces.size()); }
  int loop_size(int f) const { return int(p.faces[f].loop.size()); }
  Vector3d loop_vertex(int f, int k) const { return vertex(p.faces[f].loop[k]); }
  Vector3d face_normal(int f) const { return pose.turn(p.faces[f].normal); }
  double face_offset(int f) const { return p.faces[f].offset + face_normal(f).dot(pose.t); }
  int edges() const { return int(p.edges.size()); }
  Vector3d edge_direction(int k) const {
    return pose.turn((p.vertices[p.edges[k].v1] - p.vertices[p.edges[k].v0]).stableNormalized());
  }
  bool arc(int k, Vector3d& n0, Vector3d& n1, Vector3d& on) const {
    if (p.flat) return false;
    n0 = face_normal(p.edges[k].left), n1 = face_normal(p.edges[k].right);
    on = vertex(p.edges[k].v0);
    return true;
  }
  // At least the largest |coordinate|, without a pass over the vertices.
  double reach() const { return pose.t.cwiseAbs().maxCoeff() + radius; }
  const double radius = 0;                                // at least the largest |x| in the body frame
  const double *x = nullptr, *y = nullptr, *z = nullptr;  // the body-frame vertices as arrays
  // The body frame, where a pass over vertices or faces reads the polytope as stored.
  Vector3d to_body(const Vector3d& d) const { return pose.to_body(d); }
  Vector3d body_point(const Vector3d& x) const { return pose.body_point(x); }
  double shift(const Vector3d& d) const { return pose.shift(d); }
  const Vector3d& body_vertex(int k) const { return p.vertices[k]; }
  const Vector3d& body_loop_vertex(int f, int k) const { return p.vertices[p.faces[f].loop[k]]; }
  const Vector3d& body_normal(int f) const { return p.faces[f].normal; }
  double body_offset(int f) const { return p.faces[f].offset; }
};

}  // namespace

[[gnu::noinline]] void detail::wide_scan(const double* x, const double* y, const double* z, int n, double nx, double ny,
                                         double nz, double& top, int& arg) {
  support_push(x, y, z, n, &nx, &ny, &nz, 1, &top, &arg);
}

namespace {

// The support of a posed shape with the direction turned into the body frame (one product
// per vertex instead of a pose per vertex; a large shape's by the SIMD kernel).
[[gnu::flatten]] int highest(const PosedShape& s, const Vector3d& n, double& value) {
  const Vector3d nb = s.to_body(n);
  int best = 0;
  double top = -std::numeric_limits<double>::infinity();  // (a local: not re-read through `value`)
  if (s.size() >= detail::kWideScan) {
    detail::wide_scan(s.x, s.y, s.z, s.size(), nb.x(), nb.y(), nb.z(), top, best);
  } else {
    for (int k = 0; k < s.size(); ++k)
      if (const double x = nb.dot(s.p.vertices[k]); x > top) top = x, best = k;
  }
  value = top + s.shift(n);
  return best;
}

// Whether the Gauss-map arcs a0-a1 (an edge of A) and c0-c1 (an edge of -B, its face normals
// negated) cross: only then is the cross product of the two edges a facet normal of A (-) B
// (Gregorius, "The separating axis test between convex polyhedra", GDC 2013). Arcs that only
// touch give no new normal: the touching point is a face normal, a candidate anyway.
bool arcs_cross(const Vector3d& a0, const Vector3d& a1, const Vector3d& c0, const Vector3d& c1) {
  const Vector3d na = a1.cross(a0), nc = c1.cross(c0);
  const double c0a = c0.dot(na), c1a = c1.dot(na), a0c = a0.dot(nc), a1c = a1.dot(nc);
  return c0a * c1a < 0 && a0c * a1c < 0 && c0a * a1c > 0;
}

// |d| without underflow or overflow (coordinates of 1e-271 square to zero).
double length(const Vector3d& d) {
  const double m = d.cwiseAbs().maxCoeff();
  return m > 0 && std::isfinite(m) ? m * (d / m).norm() : m;
}

template <class S>
bool inside(const S& s, const Vector3d& q) {
  if (!s.solid) return false;
  for (int f = 0; f < s.faces(); ++f)
    if (s.face_normal(f).dot(q) > s.face_offset(f)) return false;
  return true;
}

// Whether every vertex of `other` (moved by shift) lies behind face f of s by more than
// margin: then f cannot hold the nearest point of the solid s to `other`, which lies on a face
// that has that point in front.
template <class S, class T>
bool behind(const S& s, int f, const T& other, const Vector3d& shift, double margin) {
  if (!s.solid) return false;
  for (int k = 0; k < other.size(); ++k)
    if (s.face_normal(f).dot(other.vertex(k) + shift) - s.face_offset(f) >= -margin) return false;
  return true;
}

// The nearest points of A's and (B + shift)'s surfaces, over the pairs of faces that can hold
// them, each face fanned into triangles (triangle_distance is exact and robust for
// near-parallel pairs). When one solid holds the other, no face pair qualifies and the answer
// is the nearest vertex pair (the caller tests containment). Given a `contact` direction n
// along which A and B + shift touch (the plane n . x = max n . A supports both), only the
// vertices and faces of A within margin of that plane, and of B + shift, can hold the points.
template <class A, class B>
double surface_distance(const A& a, const B& b, const Vector3d& shift, double margin, Vector3d& pa, Vector3d& pb,
                        const Vector3d* contact = nullptr) {
  double top = -std::numeric_limits<double>::infinity(), bottom = -top;
  if (contact) {
    for (int i = 0; i < a.size(); ++i) top = std::max(top, contact->dot(a.vertex(i)));
    for (int j = 0; j < b.size(); ++j) bottom = std::min(bottom, contact->dot(b.vertex(j)));
    bottom += contact->dot(shift);
  }
  const auto near_a = [&](const Vector3d& v) { return !contact || contact->dot(v) >= top - margin; };
  const auto near_b = [&](const Vector3d& v) { return !contact || contact->dot(v) <= bottom + margin; };
  // The nearest pair of vertices bounds the distance from above, so that far face pairs are
  // skipped from the start.
  double best = std::numeric_limits<double>::infinity();
  for (int i = 0; i < a.size(); ++i) {
    if (!near_a(a.vertex(i))) continue;
    for (int j = 0; j < b.size(); ++j)
      if (const Vector3d v = b.vertex(j) + shift; near_b(v))
        if (const double d = length(a.vertex(i) - v); d < best) best = d, pa = a.vertex(i), pb = v;
  }
  // How far the points x_k (k < count) all lie on one side of the plane n . x = offset: a lower
  // bound of the distance between the face on that plane and their face.
  const auto gap = [](const Vector3d& n, double offset, int count, const auto& x) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int k = 0; k < count; ++k) {
      const double h = n.dot(x(k)) - offset;
      lo = std::min(lo, h), hi = std::max(hi, h);
    }
    return std::max({lo, -hi, 0.0});
  };
  // Triangle pairs go to the batched kernel 16 at a time (on the stack: no allocation); the
  // face-pair bound is checked against the best distance of the batches done so far.
  detail::TrianglePairs batch;
  const auto flush = [&] {
    batch.flush([&](double d, const Vector3d& p, const Vector3d& q, int, int) {
      if (d < best) best = d, pa = p, pb = q;
    });
  };
  // Whether a face has a vertex near the contact plane.
  const auto touches = [](int size, const auto& near, const auto& x) {
    for (int k = 0; k < size; ++k)
      if (near(x(k))) return true;
    return false;
  };
  for (int f = 0; f < a.faces(); ++f) {
    if (!touches(a.loop_size(f), near_a, [&](int k) { return a.loop_vertex(f, k); })) continue;
    if (behind(a, f, b, shift, margin)) continue;
    for (int g = 0; g < b.faces(); ++g) {
      if (!touches(b.loop_size(g), near_b, [&](int k) { return Vector3d(b.loop_vertex(g, k) + shift); })) continue;
      if (behind(b, g, a, -shift, margin)) continue;
      const Vector3d& nf = a.face_normal(f);
      const Vector3d& ng = b.face_normal(g);
      const double apart = std::max(
          gap(nf, a.face_offset(f), b.loop_size(g), [&](int k) { return Vector3d(b.loop_vertex(g, k) + shift); }),
          gap(ng, b.face_offset(g) + ng.dot(shift), a.loop_size(f), [&](int k) { return a.loop_vertex(f, k); }));
      if (apart >= best) continue;
      // Each face fanned from its first vertex (with a contact plane: the triangles that reach it).
      for (int i = 1; i + 1 < a.loop_size(f); ++i) {
        const Vector3d s[3] = {a.loop_vertex(f, 0), a.loop_vertex(f, i), a.loop_vertex(f, i + 1)};
        if (!near_a(s[0]) && !near_a(s[1]) && !near_a(s[2])) continue;
        for (int j = 1; j + 1 < b.loop_size(g); ++j) {
          const Vector3d t[3] = {b.loop_vertex(g, 0) + shift, b.loop_vertex(g, j) + shift,
                                 b.loop_vertex(g, j + 1) + shift};
          if (!near_b(t[0]) && !near_b(t[1]) && !near_b(t[2])) continue;
          if (batch.add(s, t)) flush();
        }
      }
    }
  }
  flush();
  return best;
}

// h_M(n) = max_a n.a - min_b n.b for n and for -n.
template <class A, class B>
void support_pair(const A& a, const B& b, const Vector3d& n, double& plus, double& minus) {
  double amax = -std::numeric_limits<double>::infinity(), amin = -amax, bmax = amax, bmin = amin;
  for (int k = 0; k < a.size(); ++k) {
    const double x = n.dot(a.vertex(k));
    amax = std::max(amax, x), amin = std::min(amin, x);
  }
  for (int k = 0; k < b.size(); ++k) {
    const double x = n.dot(b.vertex(k));
    bmax = std::max(bmax, x), bmin = std::min(bmin, x);
  }
  plus = amax - bmin, minus = bmax - amin;
}

// The support pairs of an answer's features, kept for the next query (three, repeats
// allowed): GJK's nearest simplex, or (depth) the face of M that holds the deepest point.
// And where the answer's normal is a face normal of A (or of B, negated), that face: a sliding
// or resting contact keeps it, and the next query probes it first.
struct Features {
  int a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  bool valid = false, depth = false;
  int face = -1;
  bool face_of_b = false;
  Vector3d normal = Vector3d::Zero();  // the proof's unit normal, A towards B (0: the search answered)
};

// The nearest features of separated shapes by GJK (Gilbert, Johnson & Keerthi, "A fast
// procedure for computing the distance between complex objects in three-dimensional space",
// IEEE J. Robotics and Automation 4(2), 1988) on M = A (-) B, from the support pairs
// (start_a[k], start_b[k]), k < start (a cold query: one pair; a coherent one: the last
// answer's three): returns 3 with up to three vertices of A (fa) and of B (fb) whose hulls hold
// the nearest points and the weights of its nearest point on them (summing to 1; all 0 where
// it has none), 4 with the four pairs of a tetrahedron of M around the origin, or 0 (NaN).
// Its answer is a guess, rounding and all: certified_distance, certified_depth and
// certified_touching prove it, or the caller does the exhaustive search. M's points are scaled
// by `scale`, a power of two near 1 / the coordinates' magnitude, so that their products
// neither overflow nor underflow. It runs in steps (run), so that a caller can look at its
// direction part way (see face_first).
template <class A, class B>
class Gjk {
 public:
  Gjk(const A& a, const B& b, double scale, const int* start_a, const int* start_b, int start)
      : a_(a), b_(b), scale_(scale) {
    for (int j = 0; j < start; ++j) {
      bool repeat = false;
      for (int m = 0; m < n_; ++m) repeat |= ia_[m] == start_a[j] && ib_[m] == start_b[j];
      if (!repeat) add(start_a[j], start_b[j]);
    }
  }

  /// Iterates until GJK ends (true) or `limit` iterations in all have passed (false).
  bool run(int limit = kIterations) {
    while (!ended_ && iter_ < std::min(limit, kIterations)) ended_ = step(), ++iter_;
    return ended_ || iter_ == kIterations;
  }

  /// M's nearest point so far (scaled; from B towards A), 0 before the first step.
  const Vector3d& nearest() const { return v_; }

  /// The answer (see above): 3, 4 or 0, with the features and weights.
  int features(int (&fa)[4], int (&fb)[4], double (&weight)[3]) const {
    weight[0] = weight[1] = weight[2] = 0;
    if (result_ != 3) {
      std::copy(ia_, ia_ + 4, fa), std::copy(ib_, ib_ + 4, fb);
      return result_;
    }
    for (int j = 0; j < 3; ++j) fa[j] = ia_[std::min(j, n_ - 1)], fb[j] = ib_[std::min(j, n_ - 1)];
    for (int j = 0; j < 3; ++j) weight[j] = j < n_ && n_ < 4 ? l_[j] : 0.0;
    return 3;
  }

 private:
  static constexpr int kIterations = 64;

  void add(int ka, int kb) {
    w_[n_] = scale_ * (a_.vertex(ka) - b_.vertex(kb)), ia_[n_] = ka, ib_[n_] = kb, l_[n_] = 0, ++n_;
  }

  // One iteration; true when GJK ends.
  bool step() {
    double lambda[4];
    if (!detail::nearest_on_simplex(w_, n_, lambda)) return result_ = 4, true;
    // Keep the nearest feature's points only.
    Vector3d v = Vector3d::Zero();
    int m = 0;
    for (int j = 0; j < n_; ++j)
      if (lambda[j] > 0)
        v += lambda[j] * w_[j], w_[m] = w_[j], ia_[m] = ia_[j], ib_[m] = ib_[j], l_[m] = lambda[j], ++m;
    if (m == 0) return result_ = 0, true;  // no weight left (NaN from a degenerate simplex)
    n_ = m;
    if (!(v.squaredNorm() < vv_)) {  // no progress: rounding has the last word; the best one stands
      n_ = best_n_;
      std::copy(best_a_, best_a_ + 3, ia_), std::copy(best_b_, best_b_ + 3, ib_), std::copy(best_l_, best_l_ + 3, l_);
      return true;
    }
    vv_ = v.squaredNorm(), v_ = v;
    best_n_ = n_;
    std::copy(ia_, ia_ + 3, best_a_), std::copy(ib_, ib_ + 3, best_b_), std::copy(l_, l_ + 3, best_l_);
    // M's support point in -v: A's lowest vertex along v minus B's highest.
    double lo, hi;
    const int ka = highest(a_, -v, lo), kb = highest(b_, v, hi);
    lo = -lo;
    // Stop when M reaches no further towards the origin than v does (to rounding), or repeats.
    if (!(vv_ - scale_ * (lo - hi) > 1e-13 * vv_)) return true;
    bool repeat = false;
    for (int j = 0; j < n_; ++j) repeat |= ia_[j] == ka && ib_[j] == kb;
    if (repeat || n_ == 4) return true;
    add(ka, kb);
    return false;
  }

  const A& a_;
  const B& b_;
  double scale_;
  Vector3d w_[4], v_ = Vector3d::Zero();
  int ia_[4] = {}, ib_[4] = {}, n_ = 0;
  double l_[4] = {0, 0, 0, 0};  // the weights of the nearest point of w[0, n) (0: not yet weighed)
  double vv_ = std::numeric_limits<double>::infinity();
  int best_a_[3] = {}, best_b_[3] = {}, best_n_ = 0;  // the nearest simplex so far (ties can stall)
  double best_l_[3] = {};
  int iter_ = 0, result_ = 3;
  bool ended_ = false;
};

// GJK from the start to its end (see Gjk).
template <class A, class B>
int gjk_features(const A& a, const B& b, double scale, const int* start_a, const int* start_b, int start, int (&fa)[4],
                 int (&fb)[4], double (&weight)[3]) {
  Gjk<A, B> gjk(a, b, scale, start_a, start_b, start);
  gjk.run();
  return gjk.features(fa, fb, weight);
}

// The frame of a certified answer: the unit normal n (from A towards B) of the planes that
// prove it, A's top (max n . a, at vertex ia) and B's bottom (min n . b, at vertex ib) along
// it, and whether each is reached at that vertex alone by a wide margin (every other vertex
// more than 1e4 tau away: a normal turned by rounding cannot make another vertex the top).
struct Contact {
  Vector3d n = Vector3d::Zero();
  double top = 0, bottom = 0;
  int ia = 0, ib = 0;
  bool a_single = false, b_single = false;
};

// The vertex of s highest along n, its height, and whether every other vertex lies more than
// `wide` below it.
template <class S>
int top_of(const S& s, const Vector3d& n, double wide, double& value, bool& single) {
  int best = 0;
  double first = -std::numeric_limits<double>::infinity(), second = first;
  for (int k = 0; k < s.size(); ++k) {
    const double x = n.dot(s.vertex(k));
    if (x > first)
      second = first, first = x, best = k;
    else
      second = std::max(second, x);
  }
  value = first, single = second < first - wide;
  return best;
}

// The same for a posed shape, with n turned into the body frame once.
[[gnu::flatten]] int top_of(const PosedShape& s, const Vector3d& n, double wide, double& value, bool& single) {
  const Vector3d nb = s.to_body(n);
  int best = 0;
  double first = -std::numeric_limits<double>::infinity(), second = first;
  for (int k = 0; k < s.size(); ++k) {
    const double x = nb.dot(s.p.vertices[k]);
    if (x > first)
      second = first, first = x, best = k;
    else
      second = std::max(second, x);
  }
  value = first + s.shift(n), single = second < first - wide;
  return best;
}

template <class A, class B>
Contact heights(const A& a, const B& b, const Vector3d& n, double tau) {
  Contact c;
  c.n = n;
  c.ia = top_of(a, n, 1e4 * tau, c.top, c.a_single);
  c.ib = top_of(b, Vector3d(-n), 1e4 * tau, c.bottom, c.b_single);
  c.bottom = -c.bottom;
  return c;
}

// Up to two orthonormal directions spanned by the features of one answer (each shape's points
// minus its first); -1 if they span three (the features do not lie on two parallel planes).
int feature_span(const Vector3d* s, int ns, const Vector3d* t, int nt, Vector3d (&u)[2]) {
  int rank = 0;
  const auto add = [&](Vector3d e) {
    const double len = e.norm();
    for (int k = 0; k < rank; ++k) e -= e.dot(u[k]) * u[k];
    const double rest = e.norm();
    if (!(rest > 1e-6 * len)) return true;  // dependent (or a repeated point)
    if (rank == 2) return false;
    u[rank++] = e / rest;
    return true;
  };
  for (int k = 1; k < ns; ++k)
    if (!add(s[k] - s[0])) return -1;
  for (int k = 1; k < nt; ++k)
    if (!add(t[k] - t[0])) return -1;
  return rank;
}

// The planes' proof of certified_distance for a pair p on A and q on B at distance d.
template <class A, class B>
bool distance_by_planes(const A& a, const B& b, const Vector3d* s, const Vector3d* t, double slack, double touching,
                        double tau, const Vector3d& p, const Vector3d& q, double d, Proximity& out, Contact& c) {
  if (!(d > touching + slack)) return false;
  const Vector3d n0 = (q - p) / d;
  // (Both sides: d below the planes' bound means p and q are not on A and B, as where
  // triangle_distance misjudges a triangle 1e10 long.)
  const auto proves = [&](const Vector3d& n) {
    c = heights(a, b, n, tau);
    return std::abs(d - (c.bottom - c.top)) <= slack;
  };
  bool ok = false;
  Vector3d u[2];
  if (const int rank = feature_span(s, 3, t, 3, u); rank > 0) {
    Vector3d n1 = n0;
    for (int k = 0; k < rank; ++k) n1 -= n1.dot(u[k]) * u[k];
    ok = n1.norm() > 0.5 && proves(n1.normalized());
  }
  ok = ok || proves(n0);
  // The face normals nearest n0 (of a flat shape: either side).
  const auto nearest_face = [&](const auto& shape, double sign) {
    const Vector3d nb = sign * shape.to_body(n0);
    int best = 0;
    double align = -2;
    for (int f = 0; f < shape.faces(); ++f) {
      double x = shape.body_normal(f).dot(nb);
      if (!shape.solid) x = std::abs(x);
      if (x > align) align = x, best = f;
    }
    Vector3d nf = sign * shape.face_normal(best);
    return Vector3d(!shape.solid && nf.dot(n0) < 0 ? -nf : nf);
  };
  ok = ok || proves(nearest_face(a, 1.0)) || proves(nearest_face(b, -1.0));
  if (!ok) return false;
  out.distance = d, out.point_a = p, out.point_b = q;
  return true;
}

// The distance of separated shapes from the features GJK settles on, proven: nearest points
// p, q of the features' hulls (see below; repeated vertices allowed), d = |q - p|,
// and a unit n with A below the plane n . x = top and B above n . x = bottom: no pair of points
// is nearer than bottom - top, so d is the distance to within d - (bottom - top), kept when
// that is at most `slack` and d > touching + slack. The candidates for n, best first:
// q - p made orthogonal to the directions the features span (exactly orthogonal to the nearest
// sets when they are a face, an edge or parallel edges, where q - p alone is turned by
// rounding / d, which a face of size L lifts L * rounding / d above its plane), q - p itself,
// and the face normals of A and of B nearest it. Otherwise false (p, q and d are still set).
// The pair is GJK's own nearest point first (its weights on s and t): the features' nearest
// pair to rounding wherever GJK converged, at no cost (triangle_distance was a third of a
// coherent query); where no plane proves it, their exact nearest pair (triangle_distance).
template <class A, class B>
bool certified_distance(const A& a, const B& b, const Vector3d* s, const Vector3d* t, const double (&weight)[3],
                        double slack, double touching, double tau, Vector3d& p, Vector3d& q, double& d, Proximity& out,
                        Contact& c) {
  if (std::abs(weight[0] + weight[1] + weight[2] - 1) <= 1e-12) {
    p = weight[0] * s[0] + weight[1] * s[1] + weight[2] * s[2];
    q = weight[0] * t[0] + weight[1] * t[1] + weight[2] * t[2];
    d = length(q - p);
    if (distance_by_planes(a, b, s, t, slack, touching, tau, p, q, d, out, c)) return true;
    // (p and q lie on A and B, so the features' nearest pair is no farther apart: within
    // touching + slack, no plane proves a distance from it either.)
    if (!(d > touching + slack)) return false;
  }
  const Vector3d s3[3] = {s[0], s[1], s[2]}, t3[3] = {t[0], t[1], t[2]};
  d = triangle_distance(s3, t3, p, q);
  return distance_by_planes(a, b, s, t, slack, touching, tau, p, q, d, out, c);
}

// Which feature of a shape a level set is: a face, or one or two vertices (a vertex, an edge).
struct LevelFeature {
  int face = -1;
  int vertex[2] = {-1, -1};
};

// The vertices of s on its level plane (sign +1: A's top, -1: B's bottom) seen along n in the
// basis (u, w): a face's loop when every vertex of the face nearest n is within tau of the
// level, else the one or two vertices within tau (an edge). False for more (GJK's witnesses).
// The feature goes to `which` when asked.
template <class S>
bool level_set(const S& s, const Vector3d& n, double level, double sign, double tau, const Vector3d& u,
               const Vector3d& w, Patch& out, LevelFeature* which = nullptr) {
  // (In the body frame: a posed shape's faces and vertices are read as stored.)
  const Vector3d nb = s.to_body(n), ub = s.to_body(u), wb = s.to_body(w);
  const double lb = level - s.shift(n), su = s.shift(u), sw = s.shift(w);
  const auto on = [&](const Vector3d& x) { return sign * (nb.dot(x) - lb) >= -tau; };
  const auto put = [&](const Vector3d& x) { out.p[out.size++] = Eigen::Vector2d(ub.dot(x) + su, wb.dot(x) + sw); };
  int face = -1;
  double align = -2;
  for (int f = 0; f < s.faces(); ++f) {
    double x = sign * s.body_normal(f).dot(nb);
    if (!s.solid) x = std::abs(x);
    if (x > align) align = x, face = f;
  }
  out.size = 0;
  if (face >= 0 && s.loop_size(face) <= kPatch) {
    bool all = true;
    for (int k = 0; k < s.loop_size(face) && all; ++k) all = on(s.body_loop_vertex(face, k));
    if (all) {
      for (int k = 0; k < s.loop_size(face); ++k) put(s.body_loop_vertex(face, k));
      if (area2(out) < 0) std::reverse(out.p, out.p + out.size);
      settle(out, tau);
      if (which) *which = LevelFeature{face, {-1, -1}};
      return true;
    }
  }
  out.size = 0;
  for (int k = 0; k < s.size(); ++k)
    if (on(s.body_vertex(k))) {
      if (out.size == 2) return false;
      if (which) which->face = -1, which->vertex[out.size] = k;
      put(s.body_vertex(k));
    }
  settle(out, tau);
  return out.size > 0;
}

// The witnesses of a certified answer from its contact frame c (see Patch): each on its
// level plane, their difference (bottom - top) n; false (and left as they are) where A's and
// B's level sets do not meet seen along n, or have more than kPatch vertices.
// A certified distance or depth has proven that they meet: then a set that is one vertex gives
// the witnesses at once (`proven`); the touching certificate asks.
template <class A, class B>
bool contact_witnesses(const A& a, const B& b, const Contact& c, double tau, Vector3d& pa, Vector3d& pb,
                       bool proven = true) {
  const Vector3d gap = (c.bottom - c.top) * c.n;
  if (proven && c.a_single) return pa = a.vertex(c.ia), pb = pa + gap, true;
  if (proven && c.b_single) return pb = b.vertex(c.ib), pa = pb - gap, true;
  const Vector3d u = c.n.unitOrthogonal(), w = c.n.cross(u);
  Patch P, Q;
  if (!level_set(a, c.n, c.top, 1.0, tau, u, w, P) || !level_set(b, c.n, c.bottom, -1.0, tau, u, w, Q)) return false;
  Eigen::Vector2d x;
  if (!patch_point(P, Q, tau, x)) return false;
  pa = x.x() * u + x.y() * w + c.top * c.n;
  pb = pa + gap;
  return true;
}

// Touching, proven by a common supporting plane: a unit n along which A's top and B's bottom
// are within `touching` of each other (a separating axis along which they overlap by at most
// that: the depth is at most that), and A's and B's sets on that level meet (points of each
// within touching of each other, to tau: the distance is at most that). Intersecting, at
// distance 0 and depth max(0, top - bottom), with the patch's witnesses. The candidates for n
// are the planes of A's faces through p and of B's faces through q (negated; p and q are
// GJK's guesses of a contact point), then the cross product of the features' two edge
// directions (an edge across an edge), each sign; at most four are tried, those that the
// features (s on A, t on B) least contradict first (a guess: GJK's features near touching
// may lie anywhere on the contact's planes).
template <class A, class B>
bool certified_touching(const A& a, const B& b, const Vector3d& p, const Vector3d& q, const Vector3d* s,
                        const Vector3d* t, int count, double touching, double tau, double margin, Proximity& out,
                        Contact& c) {
  // (GJK slows down near touching: its points may be a few 1e-9 of the size apart there. They
  // only locate the candidate planes; the planes and the level sets are the proof.)
  const double near = std::max(margin, 4 * length(p - q));
  if (!(near <= 1e3 * margin)) return false;
  constexpr int kMax = 16;
  Vector3d cand[kMax];
  double score[kMax];
  int n = 0;
  const auto add = [&](const Vector3d& nc) {
    if (n == kMax || !(nc.squaredNorm() > 0.25)) return;
    double hi = -std::numeric_limits<double>::infinity(), lo = -hi;
    for (int k = 0; k < count; ++k) hi = std::max(hi, nc.dot(s[k])), lo = std::min(lo, nc.dot(t[k]));
    cand[n] = nc, score[n] = lo - hi, ++n;
  };
  const auto faces_through = [&](const auto& shape, const Vector3d& x, double sign) {
    const Vector3d xb = shape.body_point(x);
    for (int f = 0; f < shape.faces(); ++f) {
      if (!(std::abs(shape.body_normal(f).dot(xb) - shape.body_offset(f)) <= near)) continue;
      const Vector3d nf = shape.face_normal(f);
      add(sign * nf);
      if (!shape.solid) add(-sign * nf);
    }
  };
  faces_through(a, p, 1.0), faces_through(b, q, -1.0);
  Vector3d u[2];
  if (feature_span(s, count, t, 0, u) == 1) {
    Vector3d v[2];
    if (feature_span(t, count, s, 0, v) == 1 && u[0].cross(v[0]).norm() > 1e-6) {
      const Vector3d x = u[0].cross(v[0]).normalized();
      add(x), add(-x);
    }
  }
  for (int tries = 0; tries < 4 && n > 0; ++tries) {
    const int best = int(std::max_element(score, score + n) - score);
    if (score[best] == -std::numeric_limits<double>::infinity()) return false;
    score[best] = -std::numeric_limits<double>::infinity();
    c = heights(a, b, cand[best], tau);
    Vector3d pa, pb;
    if (!(std::abs(c.bottom - c.top) <= touching) || !contact_witnesses(a, b, c, tau, pa, pb, false)) continue;
    out.intersecting = true;
    out.distance = 0;
    out.penetration_depth = std::max(0.0, c.top - c.bottom);
    out.penetration_direction = c.n;
    out.point_a = pa, out.point_b = pb;
    return true;
  }
  return false;
}

// The penetration of overlapping shapes from the tetrahedron of M around the origin that GJK
// ends with, by the expanding polytope algorithm (van den Bergen, "Proximity queries and
// penetration depth computation on 3D game objects", GDC 2001), in fixed buffers: P, a closed
// triangulated surface of points of M around the origin, grows towards M's facet nearest the
// origin. Proven: if every face of P lies farther than `touching` from the origin, the ray from
// the origin along the depth direction leaves M (at the depth) no sooner than it crosses P, so
// the least face distance d is at most the depth; and the support h_M(n) along that face's
// normal is at least the depth. Kept when h_M(n) - d <= slack, with the origin's projection
// d n inside the face, whose corners give the witnesses on A and B. Otherwise false: the
// caller searches exhaustively.
template <class A, class B>
MINKSUM_FLATTEN bool certified_depth(const A& a, const B& b, const int (&ta)[4], const int (&tb)[4], double slack,
                                     double touching, Proximity& out, Features* facet = nullptr) {
  constexpr int kPoints = 64, kFaces = 128;
  struct Face {
    int v[3];
    Vector3d n;
    double d;
  };
  Vector3d w[kPoints];
  int ia[kPoints], ib[kPoints], np = 0;
  Face face[kFaces];
  int nf = 0;
  // Face u, v, x (counter-clockwise seen from outside), kept only with the origin inside by
  // more than `touching` and than the rounding of its offset d: the points carry eps |w| each,
  // which turns the normal by eps W (|e1| + |e2|) / |e1 x e2| (and the cross product's own
  // rounding by eps |e1| |e2| / |e1 x e2|), and d by that times W. (Faces between a needle's
  // far end, 1e10 away, and points 40 apart have normals turned by 1e-7: unchecked, they give
  // an origin 24.7 outside M a "depth" of 4.6.)
  const auto add = [&](int u, int v, int x) {
    if (nf == kFaces) return false;
    const Vector3d e1 = w[v] - w[u], e2 = w[x] - w[u];
    Vector3d n = e1.cross(e2);
    const double len = n.norm();
    if (!(len > 0) || !std::isfinite(len)) return false;
    n /= len;
    const double d = n.dot(w[u]);
    const double W = std::max({w[u].norm(), w[v].norm(), w[x].norm()}), l1 = e1.norm(), l2 = e2.norm();
    const double rounding = 8 * std::numeric_limits<double>::epsilon() * W * (l1 * l2 + W * (l1 + l2) + len) / len;
    if (!(d > touching + rounding)) return false;
    face[nf++] = {{u, v, x}, n, d};
    return true;
  };
  for (int k = 0; k < 4; ++k) w[k] = a.vertex(ta[k]) - b.vertex(tb[k]), ia[k] = ta[k], ib[k] = tb[k];
  np = 4;
  static constexpr int kTet[4][4] = {{0, 1, 2, 3}, {0, 3, 1, 2}, {0, 2, 3, 1}, {1, 3, 2, 0}};
  // A sliver tetrahedron's orientation is rounding (of a needle 1e3 times longer than wide,
  // faces come out wound both ways, and separated shapes get a "depth"): none of it is
  // trusted below 1e-9 of its edges' product.
  const Vector3d e1 = w[1] - w[0], e2 = w[2] - w[0], e3 = w[3] - w[0];
  if (!(std::abs(e1.cross(e2).dot(e3)) > 1e-9 * e1.norm() * e2.norm() * e3.norm())) return false;
  for (const auto& t : kTet) {  // wound so that the fourth point is behind
    const bool flip = (w[t[1]] - w[t[0]]).cross(w[t[2]] - w[t[0]]).dot(w[t[3]] - w[t[0]]) > 0;
    if (!(flip ? add(t[0], t[2], t[1]) : add(t[0], t[1], t[2]))) return false;
  }
  for (int iter = 0; iter < kPoints; ++iter) {
    int best = 0;
    for (int k = 1; k < nf; ++k)
      if (face[k].d < face[best].d) best = k;
    const Face f = face[best];
    // M's support along f's normal: A's highest vertex minus B's lowest.
    double hi, lo;
    const int ka = highest(a, f.n, hi), kb = highest(b, -f.n, lo);
    lo = -lo;
    if (hi - lo - f.d <= slack) {
      // The origin's projection x = d n in barycentric coordinates of a face holding it: this
      // one, or another in its plane (M's facet may be split into several faces of P).
      const Vector3d x = f.d * f.n;
      for (int g = 0; g < nf; ++g) {
        const Face& h = face[g];
        if (!(std::abs(h.n.dot(x) - h.d) <= slack)) continue;
        const Vector3d &p0 = w[h.v[0]], &p1 = w[h.v[1]], &p2 = w[h.v[2]];
        const double area = (p1 - p0).cross(p2 - p0).dot(h.n);
        const double l1 = (x - p0).cross(p2 - p0).dot(h.n) / area, l2 = (p1 - p0).cross(x - p0).dot(h.n) / area;
        const double l0 = 1 - l1 - l2;
        if (!(l0 >= -1e-9 && l1 >= -1e-9 && l2 >= -1e-9)) continue;
        out.intersecting = true;
        out.penetration_depth = f.d, out.penetration_direction = f.n;
        out.point_a = l0 * a.vertex(ia[h.v[0]]) + l1 * a.vertex(ia[h.v[1]]) + l2 * a.vertex(ia[h.v[2]]);
        out.point_b = l0 * b.vertex(ib[h.v[0]]) + l1 * b.vertex(ib[h.v[1]]) + l2 * b.vertex(ib[h.v[2]]);
        if (facet) {  // the support pairs of the face that holds the answer, for the next query
          for (int j = 0; j < 3; ++j) facet->a[j] = ia[h.v[j]], facet->b[j] = ib[h.v[j]];
          facet->valid = facet->depth = true;
        }
        return true;
      }
      return false;
    }
    if (np == kPoints) return false;
    const int q = np++;
    w[q] = a.vertex(ka) - b.vertex(kb), ia[q] = ka, ib[q] = kb;
    // Remove the faces q sees (clearly: rounding must not decide), keeping their edges; the
    // ones whose reverse is not kept bound the hole (the horizon), which must be one loop.
    int edge[3 * kFaces][2], ne = 0, kept = 0;
    for (int k = 0; k < nf; ++k) {
      if (face[k].n.dot(w[q]) - face[k].d > slack) {  // (q in a face's plane: kept)
        for (int e = 0; e < 3; ++e) edge[ne][0] = face[k].v[e], edge[ne][1] = face[k].v[(e + 1) % 3], ++ne;
      } else {
        face[kept++] = face[k];
      }
    }
    nf = kept;
    int horizon[3 * kFaces][2], nh = 0;
    for (int e = 0; e < ne; ++e) {
      bool inner = false;
      for (int g = 0; g < ne && !inner; ++g) inner = edge[g][0] == edge[e][1] && edge[g][1] == edge[e][0];
      if (!inner) horizon[nh][0] = edge[e][0], horizon[nh][1] = edge[e][1], ++nh;
    }
    if (nh < 3) return false;
    for (int e = 0, at = horizon[0][1], steps = 1;; ++steps) {  // one loop through every edge
      int next = -1;
      for (int g = 0; g < nh; ++g)
        if (horizon[g][0] == at) next = next < 0 ? g : nh;  // two edges leaving one point: nh
      if (next < 0 || next == nh) return false;
      at = horizon[next][1];
      if (next == e) {
        if (steps != nh) return false;
        break;
      }
      if (steps > nh) return false;
    }
    for (int e = 0; e < nh; ++e)
      if (!add(horizon[e][0], horizon[e][1], q)) return false;
  }
  return false;
}

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

// The tolerances of one query, from the largest coordinate of its shapes (reach; a bound for a
// posed shape, so that the cold and the coherent query use the same): `slack`, what a
// certificate may leave between its bounds (the supports' rounding); `touching`, the distance
// and depth within which the shapes touch; `tau`, how far below its top a vertex still counts
// as on it (the patch's level sets); `margin`, how far from a face's plane a point still
// counts as on it (the touching certificate's candidates).
struct Tolerances {
  double reach, k, slack, touching, tau, margin;
};

template <class A, class B>
Tolerances tolerances(const A& a, const B& b) {
  Tolerances t;
  t.reach = std::max(a.reach(), b.reach());
  t.k = detail::scale_to_one(t.reach);  // scaled squared lengths neither overflow nor underflow
  t.slack = 64 * std::numeric_limits<double>::epsilon() * t.reach;
  t.touching = t.slack, t.tau = 4 * t.slack, t.margin = 1e-9 * t.reach;
  return t;
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

// Box pairs whose nearest (or deepest) sets are patches, a face or an edge of each across the
// contact normal (a box resting, sliding or rocking on a box): the witnesses are the patch's
// (patch_point), as for prepared shapes, so that they do not jump between corners and
// the coherent answer's equal the cold one's. The normal is snapped to the axis of A or B it
// is within 1.4e-6 rad of (the box pair's normal of a 1e-12 gap is turned by rounding / gap)
// where that still proves the answer: the gap between the boxes' levels along it is the
// distance (or the depth) to 64 eps of the coordinates; else the pair's normal, if that does.
void box_patch(const Box& a, const Box& b, Proximity& out) {
  Vector3d n = out.intersecting ? out.penetration_direction : Vector3d(out.point_b - out.point_a);
  if (!(n.norm() > 0)) return;
  n.normalize();
  double align = 0;
  Vector3d axis = n;
  for (const Box* x : {&a, &b})
    for (int k = 0; k < 3; ++k)
      if (const double d = n.dot(x->rotation.col(k)); std::abs(d) > align)
        align = std::abs(d), axis = (d < 0 ? -1.0 : 1.0) * x->rotation.col(k);
  const double reach = std::max(
      {a.center.cwiseAbs().maxCoeff() + a.half_extents.sum(), b.center.cwiseAbs().maxCoeff() + b.half_extents.sum()});
  const double eps = std::numeric_limits<double>::epsilon();
  const double tau = 256 * eps * reach, gap = out.intersecting ? -out.penetration_depth : out.distance;
  for (int snapped = 1; snapped >= 0; --snapped) {
    if (snapped && !(align > 1 - 1e-12)) continue;
    const Vector3d m = snapped ? Vector3d(axis.normalized()) : n;
    detail::BoxLevel la, lb;
    if (!detail::box_level_of(a, m, 1.0, tau, la) || !detail::box_level_of(b, m, -1.0, tau, lb)) continue;
    // A corner: the pair's witnesses are the only ones (most poses end here, before the sets).
    if (la.nfree == 0 || lb.nfree == 0) return;
    const Vector3d u = m.unitOrthogonal(), w = m.cross(u);
    Patch P, Q;
    detail::level_patch(a, la, tau, u, w, P), detail::level_patch(b, lb, tau, u, w, Q);
    if (P.size == 1 || Q.size == 1) return;  // (a speck of an edge or face, settled to a point)
    const double top = m.dot(la.base), bottom = m.dot(lb.base);
    if (!(std::abs(bottom - top - gap) <= 64 * eps * reach)) continue;
    Eigen::Vector2d x;
    if (!patch_point(P, Q, tau, x)) return;
    out.point_a = x.x() * u + x.y() * w + top * m;
    out.point_b = out.point_a + (bottom - top) * m;
    return;
  }
}

// The face of A whose normal is n (to 1e-12), or of B whose normal is -n, into f (see Features).
template <class A, class B>
void face_normal_of(const A& a, const B& b, const Vector3d& n, Features& f) {
  const auto find = [&](const auto& s, const Vector3d& d) {
    const Vector3d db = s.to_body(d);
    for (int k = 0; k < s.faces(); ++k)
      if (s.body_normal(k).dot(db) > 1 - 1e-12) return k;
    return -1;
  };
  f.face = find(a, n), f.face_of_b = false;
  if (f.face < 0) f.face = find(b, Vector3d(-n)), f.face_of_b = true;
}

// Whether x, seen along the normal of s's face, lies within the face's loop (on its edges
// counts; either orientation of the loop).
template <class S>
[[gnu::noinline]] bool over_face(const S& s, int face, const Vector3d& x) {
  const Vector3d xb = s.body_point(x), &nb = s.body_normal(face);
  const int m = s.loop_size(face);
  double lo = 0, hi = 0;
  for (int k = 0; k < m; ++k) {
    const Vector3d &p = s.body_loop_vertex(face, k), &q = s.body_loop_vertex(face, k + 1 < m ? k + 1 : 0);
    const double side = (q - p).cross(xb - p).dot(nb);
    lo = std::min(lo, side), hi = std::max(hi, side);
  }
  return lo >= 0 || hi <= 0;
}

// The coherent probe of the last answer's face normal n (A's, or B's negated): where A's top
// and B's bottom along n are apart (or within `touching`) and their level sets meet, the
// planes prove the distance bottom - top (or touching) and the patch gives the witnesses at
// that distance: no GJK. False otherwise (pressed: the expanding polytope answers). Below
// Want::Patch, the other shape's extreme vertex over the face is enough (a point of each at
// that distance), without the level sets.
template <class A, class B>
bool face_probe(const A& a, const B& b, int face, bool of_b, const Tolerances& t, Want want, Proximity& out,
                Features& f) {
  if (face >= (of_b ? b.faces() : a.faces())) return false;
  const Vector3d n = of_b ? Vector3d(-b.face_normal(face)) : a.face_normal(face);
  const Contact c = heights(a, b, n, t.tau);
  const double gap = c.bottom - c.top;
  if (!(gap >= -t.touching)) return false;
  Vector3d pa, pb;
  if (!has(want, Want::Patch) && !of_b && over_face(a, face, b.vertex(c.ib))) {
    pb = b.vertex(c.ib), pa = pb - gap * n;
  } else if (!has(want, Want::Patch) && of_b && over_face(b, face, a.vertex(c.ia))) {
    pa = a.vertex(c.ia), pb = pa + gap * n;
  } else if (!contact_witnesses(a, b, c, t.tau, pa, pb, false)) {
    return false;
  }
  out = Proximity{};
  if (gap > t.touching) {
    out.distance = gap;
  } else {
    out.intersecting = true;
    out.penetration_depth = std::max(0.0, -gap), out.penetration_direction = n;
  }
  out.point_a = pa, out.point_b = pb;
  for (int j = 0; j < 3; ++j) f.a[j] = c.ia, f.b[j] = c.ib;
  f.valid = true, f.face = face, f.face_of_b = of_b, f.normal = n;
  return true;
}

// The depth from a face of M's points (three support pairs fa[face[k]], fb[face[k]]) that the
// origin lies within rounding of: with M's support point beyond it, a tetrahedron around the
// origin for the expanding polytope when the face is on M's boundary (the coherent query's
// start from its last facet); else, with the support points on both sides, the three
// tetrahedra of that double pyramid (the origin lies in one).
template <class A, class B>
bool depth_from_face(const A& a, const B& b, const int* fa, const int* fb, const int (&face)[3], const Tolerances& t,
                     Proximity& out, Features* f) {
  Vector3d w[3];
  for (int j = 0; j < 3; ++j) w[j] = t.k * (a.vertex(fa[face[j]]) - b.vertex(fb[face[j]]));
  Vector3d n = (w[1] - w[0]).cross(w[2] - w[0]);
  if (n.dot(w[0]) < 0) n = -n;  // towards the face, away from the origin
  double unused;
  const int ia[3] = {fa[face[0]], fa[face[1]], fa[face[2]]}, ib[3] = {fb[face[0]], fb[face[1]], fb[face[2]]};
  const int below_a = highest(a, -n, unused), below_b = highest(b, n, unused);
  const int ta[4] = {ia[0], ia[1], ia[2], below_a}, tb[4] = {ib[0], ib[1], ib[2], below_b};
  if (certified_depth(a, b, ta, tb, t.slack, t.touching, out, f)) return true;
  const int above_a = highest(a, n, unused), above_b = highest(b, -n, unused);
  for (int j = 0; j < 3; ++j) {
    const int k = (j + 1) % 3;
    const int sa[4] = {ia[j], ia[k], above_a, below_a}, sb[4] = {ib[j], ib[k], above_b, below_b};
    if (certified_depth(a, b, sa, sb, t.slack, t.touching, out, f)) return true;
  }
  return false;
}

// The depth where GJK ends with the origin within rounding of its simplex (pressed face to
// face, M's facet holds its triangle; pressed by 1e-12 of the size, its tetrahedron is too
// flat for the expanding polytope): from each face of it in turn.
template <class A, class B>
bool depth_from_faces(const A& a, const B& b, int found, const int (&fa)[4], const int (&fb)[4], const Tolerances& t,
                      Proximity& out, Features* f) {
  static constexpr int kFace[4][3] = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {1, 2, 3}};
  for (int k = 0; k < (found == 4 ? 4 : 1); ++k)
    if (depth_from_face(a, b, fa, fb, kFace[k], t, out, f)) return true;
  return false;
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

// The exhaustive search, the last resort where no certificate holds (GJK's features are a
// guess, rounding and all). Distance: the nearest pair of surface points over the face pairs
// that can hold them, O(F_A F_B) pairs with bounds that skip most, or 0 if the surfaces meet
// (within `touching`) or one shape holds the other. Penetration: every facet normal of
// M = A (-) B is a face normal of A or B or the cross product of an edge of each (the Gauss
// map), and h_M(n) >= depth for every unit n, so the least h_M over those candidates (both
// signs) is the depth, O((F_A + F_B + crossing arcs) (V_A + V_B)); the deepest points are the
// nearest points of A and of B moved by depth * n, where they touch.
template <class A, class B>
void searched_proximity(const A& a, const B& b, int found, const Tolerances& t, Proximity& out) {
  out.searched = true;
  Vector3d alo = a.vertex(0), ahi = alo, blo = b.vertex(0), bhi = blo;
  for (int i = 1; i < a.size(); ++i) alo = alo.cwiseMin(a.vertex(i)), ahi = ahi.cwiseMax(a.vertex(i));
  for (int j = 1; j < b.size(); ++j) blo = blo.cwiseMin(b.vertex(j)), bhi = bhi.cwiseMax(b.vertex(j));
  const double size = std::max((ahi - blo).maxCoeff(), (bhi - alo).maxCoeff());
  const double tol = t.touching;
  enum class Guess { Separated, Overlapping };
  const Guess guess = found == 4 ? Guess::Overlapping : Guess::Separated;
  double depth = std::numeric_limits<double>::infinity();
  Vector3d dir = Vector3d::UnitZ();
  const auto deepest = [&] {
    const auto consider = [&](const Vector3d& n) {
      double plus, minus;
      support_pair(a, b, n, plus, minus);
      if (plus < depth) depth = plus, dir = n;
      if (minus < depth) depth = minus, dir = -n;
    };
    for (int f = 0; f < a.faces(); ++f) consider(a.face_normal(f));
    for (int f = 0; f < b.faces(); ++f) consider(b.face_normal(f));
    // Edge crosses, skipping pairs whose Gauss-map arcs do not cross (not facets of M). Where
    // they cross at n, edge i of A and edge j of B are the supports along n and -n, so
    // n . (a - b) for points a, b of the edges is h_M(n); it is a point of M, so never above
    // h_M(n) whatever the rounding: no less than the depth so far, it cannot lower it, and the
    // scan is skipped.
    for (int i = 0; i < a.edges(); ++i) {
      const Vector3d ea = a.edge_direction(i);
      Vector3d a0 = Vector3d::Zero(), a1 = a0, b0 = a0, b1 = a0, pa = a0, pb = a0;
      const bool arc_a = a.arc(i, a0, a1, pa);
      for (int j = 0; j < b.edges(); ++j) {
        const bool arcs = arc_a && b.arc(j, b0, b1, pb);
        if (arcs && !arcs_cross(a0, a1, -b0, -b1)) continue;
        const Vector3d c = ea.cross(b.edge_direction(j));
        const double len = c.norm();
        if (!(len > 0 && std::isfinite(len))) continue;
        if (arcs) {  // n towards the crossing
          const Vector3d n = (c.dot(a0 + a1) < 0 ? -1 : 1) * c / len;
          if (n.dot(pa - pb) >= depth) continue;
        }
        consider(c / len);
      }
    }
  };
  // Overlapping by GJK: the depth first. Positive along every candidate axis (face normals,
  // edge crosses), it proves the overlap by the separating axis theorem, and the search for
  // the nearest surface points is not needed.
  if (guess == Guess::Overlapping) deepest();
  if (guess == Guess::Separated || !(depth > tol)) {
    const double best = surface_distance(a, b, Vector3d::Zero(), 1e-9 * size, out.point_a, out.point_b);
    if (best > tol && !inside(a, b.vertex(0)) && !inside(b, a.vertex(0))) {
      out.distance = best;
      return;
    }
    if (guess != Guess::Overlapping) deepest();
  }
  out.intersecting = true;
  out.penetration_depth = std::max(0.0, depth);
  out.penetration_direction = dir;
  contact_witnesses(a, b, heights(a, b, dir, t.tau), t.tau, out.point_a, out.point_b);
}

// GJK crawls where a face meets a face or an edge (apart by little, touching or nearly): the
// origin lies on or near a facet of M whose vertices tie, and each step gains little (6 to 10
// steps on the face-to-face budgets' rows, each a support of both shapes). After kFaceFirst
// steps its direction v (M's nearest point so far, from B towards A) names the face of A and
// of B most nearly facing the other; the more aligned one is probed (face_probe, the
// coherent query's certificate) where its normal is within 0.8 degrees of v. The budgets'
// face-to-face rows, touching and 1e-3 apart, cost 23-56 % fewer instructions; Table 1's
// generic pair pays the passes over the faces and the probes (about 1,000 of 11,300).
constexpr int kFaceFirst = 4;

// The face of s whose outward normal is nearest n, and the cosine between them.
template <class S>
int facing(const S& s, const Vector3d& n, double& align) {
  const Vector3d nb = s.to_body(n);
  int best = -1;
  align = -2;
  for (int f = 0; f < s.faces(); ++f)
    if (const double x = s.body_normal(f).dot(nb); x > align) align = x, best = f;
  return best;
}

template <class A, class B>
bool face_first(const A& a, const B& b, const Vector3d& v, const Tolerances& t, Want want, Proximity& out,
                Features& f) {
  if (!a.solid || !b.solid) return false;
  const double len = v.norm();
  if (!(len > 0)) return false;
  const Vector3d n = -v / len;  // from A towards B
  double align_a, align_b;
  const int face_a = facing(a, n, align_a), face_b = facing(b, Vector3d(-n), align_b);
  const bool of_b = align_b > align_a;
  if (!(std::max(align_a, align_b) > 0.9999)) return false;
  return face_probe(a, b, of_b ? face_b : face_a, of_b, t, want, out, f);
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

// A prepared shape placed by a pose.
PosedShape posed(const ConvexShape& s, const Eigen::Isometry3d& pose) {
  const detail::ShapeData* d = detail::ShapeAccess::data(s);
  const ConvexPolytope& p = s.polytope();
  const double radius = std::sqrt(3.0) * d->size;
  return PosedShape{p, {pose.linear(), pose.translation()}, !p.flat, radius, d->px.data(), d->py.data(), d->pz.data()};
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
    box_answer(placed_box(da, pose_a), placed_box(db, pose_b), cache, out, want);
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
    if (decided == BoxPatch::Apart) box_answer(x, y, nullptr, p, Want::Witnesses);
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
