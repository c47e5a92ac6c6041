// The face probes: a face normal of A or B (the last answer's, or the one GJK's direction
// names part way) proves the distance or the depth by its planes alone, without GJK's end.
// Templates over the shape views (views.hpp), included by query.cpp alone: one translation
// unit instantiates them, so that the calls between the query's parts stay inline.
#pragma once

#include "query/views.hpp"
#include "query/certificates.hpp"
#include "query/epa.hpp"

namespace minksum {
namespace {

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

}  // namespace
}  // namespace minksum
