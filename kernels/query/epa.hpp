// The penetration depth by the expanding polytope, certified.
// Templates over the shape views (views.hpp), included by query.cpp alone: one translation
// unit instantiates them, so that the calls between the query's parts stay inline.
#pragma once

#include "query/views.hpp"
#include "query/gjk.hpp"

namespace minksum {
namespace {

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

}  // namespace
}  // namespace minksum
