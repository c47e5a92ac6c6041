// The shape concept of the proximity queries: a view reads one shape (a box or a triangle in
// fixed arrays, a polytope in place, a prepared shape under a pose) through the same
// accessors, and every part of the query (GJK, the certificates, the expanding polytope, the
// face probes, the exhaustive search) is a template over two views:
//   size(), vertex(k)                      the vertices (world frame)
//   faces(), loop_size(f), loop_vertex(f,k), face_normal(f), face_offset(f)
//                                          the faces: a vertex loop, the outward unit normal and
//                                          offset (a flat shape has one face and no inside)
//   edges(), edge_direction(k), arc(k, n0, n1, on)
//                                          the edge directions and their Gauss-map arcs (none
//                                          for a box or a triangle: directions only)
//   solid, reach()                         whether it has an inside; a bound of |coordinates|
//   to_body(d), body_point(x), shift(d), body_vertex(k), body_loop_vertex(f,k), body_normal(f),
//   body_offset(f)                         the same in the body frame, where a pass over the
//                                          vertices or faces reads the shape as stored
// and highest(s, n, value), the support along n (a posed view turns n into its body frame once).
// Included by query.cpp and its parts alone: one translation unit instantiates the templates,
// so that the calls between the query's parts stay inline.
#pragma once

#include <minksum/query.hpp>
#include <minksum/shape.hpp>

#include "core/scale.hpp"
#include "geometry/rigid.hpp"
#include "query/patch.hpp"
#include "query/wide_scan.hpp"
#include "shape/shape_data.hpp"

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
namespace {

using detail::after;
using detail::area2;
using detail::cross2;
using detail::kPatch;
using detail::meets;
using detail::Patch;
using detail::patch_point;
using detail::settle;
using Eigen::Vector3d;

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


// |d| without underflow or overflow (coordinates of 1e-271 square to zero).
double length(const Vector3d& d) {
  const double m = d.cwiseAbs().maxCoeff();
  return m > 0 && std::isfinite(m) ? m * (d / m).norm() : m;
}


// A prepared shape placed by a pose.
PosedShape posed(const ConvexShape& s, const Eigen::Isometry3d& pose) {
  const detail::ShapeData* d = detail::ShapeAccess::data(s);
  const ConvexPolytope& p = s.polytope();
  const double radius = std::sqrt(3.0) * d->size;
  return PosedShape{p, {pose.linear(), pose.translation()}, !p.flat, radius, d->px.data(), d->py.data(), d->pz.data()};
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

}  // namespace
}  // namespace minksum
