// The certificates that prove GJK's answer: the distance by two planes, touching by the
// contact's level sets, and the level sets that give the witnesses.
// Templates over the shape views (views.hpp), included by query.cpp alone: one translation
// unit instantiates them, so that the calls between the query's parts stay inline.
#pragma once

#include "query/views.hpp"
#include "query/gjk.hpp"
#include "query/triangle_pairs.hpp"

namespace minksum {
namespace {

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

}  // namespace
}  // namespace minksum
