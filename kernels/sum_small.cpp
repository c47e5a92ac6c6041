// The fast path for small operands: the Gauss-map overlay of sum_fast.cpp decided in double
// with a margin, on bit sets, with no exact arithmetic and no allocation beyond the output's.
//
// For operands of at most 64 vertices, faces and edges (the paper's Table 1 solids, boxes,
// small hulls), the facets of A (+) B are (Barki et al. 2009; Fogel & Halperin 2007):
//  - face f of A (+) vertex b_j, when j is B's only support vertex along f's normal;
//  - likewise each face of B (+) A's support vertex;
//  - the parallelogram e_A (+) e_B for every pair of edges whose Gauss-map arcs cross.
// Arc e_A lies on the great circle normal to d_A = a_v1 - a_v0 (N_L x N_R is a positive
// multiple of d_A when loops run counter-clockwise from outside), so arc e_B crosses that circle
// iff exactly one of its two face normals has d_A . N > 0: the set of such e_B is the XOR, over
// the faces g of B with d_A . N_g > 0, of g's edges (each edge has two faces). The same test the
// other way and Gregorius's hemisphere condition (GDC 2013; the signs of sum_fast.cpp's
// crossing_facet) decide the crossing.
// Every sign is kept only with a margin of 1e-11 of the largest coordinate, about 10^4 times
// the rounding of the dot products; a sign within it (parallel features, touching arcs: facets
// that merge) or a result whose Euler characteristic is not 2 returns false, and the general
// path, with exact predicates, answers.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "sum_internal.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

constexpr int kMax = 64;          // vertices, faces and edges per operand (one bit each)
constexpr int kMaxCrossings = 512;
using Mask = std::uint64_t;

// One operand's edge directions and, per face, the set of its edges.
struct Operand {
  const ConvexPolytope* p;
  Vector3d dir[kMax];
  Mask edges_of[kMax];
};

// False when the operand is too large, flat, or its edges are not oriented as documented.
bool prepare(const ConvexPolytope& p, Operand& o) {
  const int E = int(p.edges.size()), F = int(p.faces.size());
  if (p.flat || p.vertices.size() > kMax || F > kMax || E > kMax) return false;
  o.p = &p;
  std::fill(o.edges_of, o.edges_of + F, Mask(0));
  for (int e = 0; e < E; ++e) {
    const Edge& ed = p.edges[e];
    o.dir[e] = p.vertices[ed.v1] - p.vertices[ed.v0];
    o.edges_of[ed.left] |= Mask(1) << e, o.edges_of[ed.right] |= Mask(1) << e;
    if (o.dir[e].dot(p.faces[ed.left].normal.cross(p.faces[ed.right].normal)) <= 0) return false;
  }
  return true;
}

// Per face of p: the vertex of q highest along its normal, by more than tol over every other.
bool unique_supports(const ConvexPolytope& p, const ConvexPolytope& q, double tol, int* support) {
  for (size_t f = 0; f < p.faces.size(); ++f) {
    const Vector3d& n = p.faces[f].normal;
    double best = -INFINITY, second = -INFINITY;
    int arg = 0;
    for (int k = 0; k < int(q.vertices.size()); ++k) {
      const double h = n.dot(q.vertices[k]);
      if (h > best) second = best, best = h, arg = k;
      else second = std::max(second, h);
    }
    if (!(best - second > tol)) return false;
    support[f] = arg;
  }
  return true;
}

// Per edge of p: the faces of q whose normal N has d . N > 0, and (the XOR of their edge sets)
// the edges of q whose arcs cross the edge's great circle. False if some |d . N| <= tol.
bool sides(const Operand& p, const Operand& q, double tol, Mask* positive, Mask* crossing) {
  const auto& faces = q.p->faces;
  for (size_t e = 0; e < p.p->edges.size(); ++e) {
    Mask pos = 0, x = 0;
    for (int g = 0; g < int(faces.size()); ++g) {
      const double s = p.dir[e].dot(faces[g].normal);
      if (!(std::abs(s) > tol)) return false;
      if (s > 0) pos |= Mask(1) << g, x ^= q.edges_of[g];
    }
    positive[e] = pos, crossing[e] = x;
  }
  return true;
}

int lowest_bit(Mask m) { return __builtin_ctzll(m); }

}  // namespace

bool sum_small(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out) {
  Operand A, B;
  if (!prepare(a, A) || !prepare(b, B)) return false;
  double size = 0;
  for (const auto* p : {&a, &b})
    for (const auto& v : p->vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  const double tol = 1e-11 * size;
  int support_in_b[kMax], support_in_a[kMax];
  Mask pos_a[kMax], cross_a[kMax], pos_b[kMax], cross_b[kMax];
  if (!unique_supports(a, b, tol, support_in_b) || !unique_supports(b, a, tol, support_in_a) ||
      !sides(A, B, tol, pos_a, cross_a) || !sides(B, A, tol, pos_b, cross_b))
    return false;

  // Facets as loops of pairs (i, j) in one flat array; a loop starts at its smallest pair.
  struct Facet {
    Vector3d normal;
    int begin, end;
  };
  constexpr int kMaxFacets = 2 * kMax + kMaxCrossings;
  Facet facets[kMaxFacets];
  std::uint8_t pi[4 * kMaxFacets + 4 * kMax], pj[4 * kMaxFacets + 4 * kMax];
  int nf = 0, np = 0;
  Mask used[kMax] = {};  // used[i] bit j: pair (i, j) is a vertex of the sum
  const auto push = [&](int i, int j) { pi[np] = std::uint8_t(i), pj[np] = std::uint8_t(j), ++np, used[i] |= Mask(1) << j; };
  const auto close = [&](const Vector3d& n, int begin) {
    int first = begin;
    for (int k = begin + 1; k < np; ++k)
      if (pi[k] < pi[first] || (pi[k] == pi[first] && pj[k] < pj[first])) first = k;
    std::rotate(pi + begin, pi + first, pi + np), std::rotate(pj + begin, pj + first, pj + np);
    facets[nf++] = {n, begin, np};
  };
  for (int f = 0; f < int(a.faces.size()); ++f) {
    const int begin = np;
    for (int i : a.faces[f].loop) push(i, support_in_b[f]);
    close(a.faces[f].normal, begin);
  }
  for (int g = 0; g < int(b.faces.size()); ++g) {
    const int begin = np;
    for (int j : b.faces[g].loop) push(support_in_a[g], j);
    close(b.faces[g].normal, begin);
  }
  for (int ea = 0; ea < int(a.edges.size()); ++ea)
    for (Mask m = cross_a[ea]; m; m &= m - 1) {
      const int eb = lowest_bit(m);
      if (!(cross_b[eb] >> ea & 1)) continue;
      const Edge &x = a.edges[ea], &y = b.edges[eb];
      // s1 = sign(d_A . N_B,left), s4 = sign(d_B . N_A,right): the arcs cross, not their
      // antipodes, when the signs agree.
      const bool s1 = pos_a[ea] >> y.left & 1, s4 = pos_b[eb] >> x.right & 1;
      if (s1 != s4) continue;
      if (nf == kMaxFacets) return false;
      // The normal is +-(d_A x d_B), on the side of the crossing point, which lies on A's arc
      // between N_L and N_R (so within 90 degrees of their sum). Nearly parallel edges: the
      // general path (its normal from the crossing point).
      Vector3d c = A.dir[ea].cross(B.dir[eb]);
      if (!(c.squaredNorm() > 1e-8 * A.dir[ea].squaredNorm() * B.dir[eb].squaredNorm())) return false;
      if (c.dot(a.faces[x.left].normal + a.faces[x.right].normal) < 0) c = -c;
      const int begin = np;
      if (!s1)  // the cell order of crossing_facet for s2 = -s1 > 0, and for s2 < 0
        push(x.v1, y.v0), push(x.v1, y.v1), push(x.v0, y.v1), push(x.v0, y.v0);
      else
        push(x.v1, y.v1), push(x.v1, y.v0), push(x.v0, y.v0), push(x.v0, y.v1);
      close(c, begin);
    }

  // Vertices in (i, j) order: pair (i, j) is number base[i] + (the pairs of row i before j).
  int base[kMax + 1];
  base[0] = 0;
  for (size_t i = 0; i < a.vertices.size(); ++i) base[i + 1] = base[i] + __builtin_popcountll(used[i]);
  const int V = base[a.vertices.size()], E = np / 2;
  if (np % 2 != 0 || V - E + nf != 2) return false;
  out.vertices.resize(V);
  for (size_t i = 0; i < a.vertices.size(); ++i) {
    int v = base[i];
    for (Mask m = used[i]; m; m &= m - 1) {
      const int j = lowest_bit(m);
      out.vertices[v++] = SumVertex{int(i), j, a.vertices[i] + b.vertices[j]};
    }
  }
  const auto index = [&](int k) { return base[pi[k]] + __builtin_popcountll(used[pi[k]] & ((Mask(1) << pj[k]) - 1)); };
  out.planes.resize(nf), out.facets.resize(nf);
  for (int k = 0; k < nf; ++k) {
    const Facet& f = facets[k];
    SumPlane& plane = out.planes[k];
    plane = SumPlane{f.normal.normalized(), -INFINITY, pi[f.begin], pj[f.begin]};
    std::vector<int>& loop = out.facets[k];
    loop.resize(f.end - f.begin);
    for (int p = f.begin; p < f.end; ++p) {
      loop[p - f.begin] = index(p);
      // The largest over the facet's vertices, as in assemble: no vertex is cut off.
      plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[loop[p - f.begin]].point));
    }
  }
  out.V = V, out.E = E, out.F = nf;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Fast;
  return true;
}

}  // namespace minksum::detail
