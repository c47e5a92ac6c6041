// The exhaustive search, where no certificate holds: the nearest surface points over the face
// pairs that can hold them, and the least support over the Gauss map's candidate normals.
// Templates over the shape views (views.hpp), included by query.cpp alone: one translation
// unit instantiates them, so that the calls between the query's parts stay inline.
#pragma once

#include "query/views.hpp"
#include "query/certificates.hpp"
#include "query/triangle_pairs.hpp"

namespace minksum {
namespace {

// Whether the Gauss-map arcs a0-a1 (an edge of A) and c0-c1 (an edge of -B, its face normals
// negated) cross: only then is the cross product of the two edges a facet normal of A (-) B
// (Gregorius, "The separating axis test between convex polyhedra", GDC 2013). Arcs that only
// touch give no new normal: the touching point is a face normal, a candidate anyway.
bool arcs_cross(const Vector3d& a0, const Vector3d& a1, const Vector3d& c0, const Vector3d& c1) {
  const Vector3d na = a1.cross(a0), nc = c1.cross(c0);
  const double c0a = c0.dot(na), c1a = c1.dot(na), a0c = a0.dot(nc), a1c = a1.dot(nc);
  return c0a * c1a < 0 && a0c * a1c < 0 && c0a * a1c > 0;
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

}  // namespace
}  // namespace minksum
