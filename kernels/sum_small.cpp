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
constexpr int kMaxCrossings = 192;  // parallelogram facets (more: the general path)
using Mask = std::uint64_t;

// One operand by component (the layout of the vertex_heights kernel, zero-padded to 8):
// vertices and face normals; its edges' endpoints; per face, the set of its edges, and per
// group of four faces the XOR of the edge sets of every subset (crossing_edges below).
struct Operand {
  const ConvexPolytope* p;
  int V, F, E;
  double vertex[3][kMax], normal[3][kMax];
  int v0[kMax], v1[kMax];
  int first[kMax];              // per face, where its loop's smallest vertex is
  Mask edges[kMax / 4][16];     // the edges of any subset of four faces (XOR of their sets)
  Mask left_edges[kMax / 4][16];  // the same for the edges whose left face is in the subset
};

// table[g][m]: the XOR of sets[4 g + b] over the bits b of m (sets zero-padded to 4).
void nibbles(const Mask* sets, int n, Mask (*table)[16]) {
  for (int g = 0; g < (n + 3) / 4; ++g) {
    table[g][0] = 0;
    for (int m = 1; m < 16; ++m) table[g][m] = table[g][m & (m - 1)] ^ sets[4 * g + __builtin_ctz(m)];
  }
}

// The XOR of the sets of the faces in `faces`, four faces per lookup.
Mask xor_of(const Mask (*table)[16], Mask faces) {
  Mask x = 0;
  for (int g = 0; faces; ++g, faces >>= 4) x ^= table[g][faces & 15];
  return x;
}

// False when the operand is too large, flat, or its edges are not oriented as documented.
bool prepare(const ConvexPolytope& p, Operand& o) {
  o.p = &p, o.V = int(p.vertices.size()), o.F = int(p.faces.size()), o.E = int(p.edges.size());
  if (p.flat || o.V > kMax || o.F > kMax || o.E > kMax) return false;
  for (int k = 0; k < o.V; ++k)
    for (int c = 0; c < 3; ++c) o.vertex[c][k] = p.vertices[k][c];
  const int padded = (o.F + 7) / 8 * 8;
  Mask edges_of[kMax] = {}, left_of[kMax] = {};
  for (int f = 0; f < padded; ++f)
    for (int c = 0; c < 3; ++c) o.normal[c][f] = f < o.F ? p.faces[f].normal[c] : 0.0;
  for (int f = 0; f < o.F; ++f) {
    const auto& loop = p.faces[f].loop;
    o.first[f] = int(std::min_element(loop.begin(), loop.end()) - loop.begin());
  }
  for (int e = 0; e < o.E; ++e) {
    const Edge& ed = p.edges[e];
    o.v0[e] = ed.v0, o.v1[e] = ed.v1;
    edges_of[ed.left] |= Mask(1) << e, edges_of[ed.right] |= Mask(1) << e, left_of[ed.left] |= Mask(1) << e;
    const Vector3d d = p.vertices[ed.v1] - p.vertices[ed.v0];
    if (d.dot(p.faces[ed.left].normal.cross(p.faces[ed.right].normal)) <= 0) return false;
  }
  nibbles(edges_of, o.F, o.edges), nibbles(left_of, o.F, o.left_edges);
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
  // The heights of A's vertices over B's face normals give B's faces' supports in A and the
  // signs d_A . N_B of A's edges; and the other way round.
  int support_in_b[kMax], support_in_a[kMax];
  Mask pos_a[kMax], pos_b[kMax], tied[2], unsure[2];
  const auto pad = [](int n) { return (n + 7) / 8 * 8; };
  if (A.V * pad(B.F) > 2048 || B.V * pad(A.F) > 2048) return false;
  vertex_heights(A.vertex[0], A.vertex[1], A.vertex[2], A.V, B.normal[0], B.normal[1], B.normal[2], B.F,
                 A.v0, A.v1, A.E, tol, support_in_a, &tied[0], pos_a, &unsure[0]);
  vertex_heights(B.vertex[0], B.vertex[1], B.vertex[2], B.V, A.normal[0], A.normal[1], A.normal[2], A.F,
                 B.v0, B.v1, B.E, tol, support_in_b, &tied[1], pos_b, &unsure[1]);
  if (tied[0] | tied[1] | unsure[0] | unsure[1]) return false;
  // Arc e_B crosses e_A's great circle iff exactly one of its faces has d_A . N > 0: the XOR,
  // over those faces, of their edge sets (each edge has two faces).
  Mask cross_a[kMax];
  for (int e = 0; e < A.E; ++e) cross_a[e] = xor_of(B.edges, pos_a[e]);
  // The same the other way, transposed: crossed_by[ea] is the set of e_B whose circle e_A
  // crosses; and b_right[f] the set of e_B with d_B . N_f > 0, for A's faces f.
  Mask crossed_by[kMax] = {}, b_right[kMax] = {};
  for (int eb = 0; eb < B.E; ++eb) {
    for (Mask m = xor_of(A.edges, pos_b[eb]); m; m &= m - 1) crossed_by[lowest_bit(m)] |= Mask(1) << eb;
    for (Mask m = pos_b[eb]; m; m &= m - 1) b_right[lowest_bit(m)] |= Mask(1) << eb;
  }

  // Facets as loops of pairs (i, j) in one flat array; `first` is the loop's smallest pair,
  // where the output loop starts (as assemble's do).
  struct Facet {
    Vector3d normal;
    int begin, end, first;
  };
  constexpr int kMaxFacets = 2 * kMax + kMaxCrossings;
  Facet facets[kMaxFacets];
  std::uint8_t pi[4 * kMaxFacets], pj[4 * kMaxFacets];
  int nf = 0, np = 0;
  Mask used[kMax] = {};  // used[i] bit j: pair (i, j) is a vertex of the sum
  const auto push = [&](int i, int j) { pi[np] = std::uint8_t(i), pj[np] = std::uint8_t(j), ++np, used[i] |= Mask(1) << j; };
  for (int f = 0; f < A.F; ++f) {
    facets[nf++] = {a.faces[f].normal, np, np + int(a.faces[f].loop.size()), np + A.first[f]};
    for (int i : a.faces[f].loop) push(i, support_in_b[f]);
  }
  for (int g = 0; g < B.F; ++g) {
    facets[nf++] = {b.faces[g].normal, np, np + int(b.faces[g].loop.size()), np + B.first[g]};
    for (int j : b.faces[g].loop) push(support_in_a[g], j);
  }
  for (int ea = 0; ea < A.E; ++ea) {
    const Edge& x = a.edges[ea];
    // s1 = sign(d_A . N_B,left), s4 = sign(d_B . N_A,right): the arcs cross, not their
    // antipodes, where the signs agree (as bit sets over e_B).
    const Mask s1 = xor_of(B.left_edges, pos_a[ea]), s4 = b_right[x.right];
    for (Mask m = cross_a[ea] & crossed_by[ea] & ~(s1 ^ s4); m; m &= m - 1) {
      const int eb = lowest_bit(m);
      const Edge& y = b.edges[eb];
      if (nf == kMaxFacets) return false;
      // The normal is +-(d_A x d_B), on the side of the crossing point, which lies on A's arc
      // between N_L and N_R (so within 90 degrees of their sum). Nearly parallel edges: the
      // general path (its normal from the crossing point).
      const Vector3d da = a.vertices[x.v1] - a.vertices[x.v0], db = b.vertices[y.v1] - b.vertices[y.v0];
      Vector3d c = da.cross(db);
      if (!(c.squaredNorm() > 1e-8 * da.squaredNorm() * db.squaredNorm())) return false;
      if (c.dot(a.faces[x.left].normal + a.faces[x.right].normal) < 0) c = -c;
      // The cell order of crossing_facet: (v1, p) (v1, q) (v0, q) (v0, p) with p, q = w0, w1
      // for s2 = -s1 > 0 and w1, w0 for s2 < 0; it starts at its smallest pair.
      const bool up = s1 >> eb & 1;
      const int p = up ? y.v1 : y.v0, q = up ? y.v0 : y.v1;
      const int first = x.v1 < x.v0 ? (p < q ? 0 : 1) : (q < p ? 2 : 3);
      facets[nf++] = {c, np, np + 4, np + first};
      push(x.v1, p), push(x.v1, q), push(x.v0, q), push(x.v0, p);
    }
  }

  // Vertices in (i, j) order, numbered through a table of the used pairs.
  const int E = np / 2;
  std::uint16_t number[kMax][kMax];
  out.vertices.clear();
  for (int i = 0; i < A.V; ++i)
    for (Mask m = used[i]; m; m &= m - 1) {
      const int j = lowest_bit(m);
      number[i][j] = std::uint16_t(out.vertices.size());
      out.vertices.push_back(SumVertex{i, j, a.vertices[i] + b.vertices[j]});
    }
  const int V = int(out.vertices.size());
  if (np % 2 != 0 || V - E + nf != 2) return false;
  out.planes.resize(nf), out.facets.resize(nf);
  for (int k = 0; k < nf; ++k) {
    const Facet& f = facets[k];
    SumPlane& plane = out.planes[k];
    plane = SumPlane{f.normal.normalized(), -INFINITY, pi[f.first], pj[f.first]};
    std::vector<int>& loop = out.facets[k];
    loop.resize(f.end - f.begin);
    for (int p = f.first, q = 0; q < f.end - f.begin; ++q, p = p + 1 == f.end ? f.begin : p + 1) {
      loop[q] = number[pi[p]][pj[p]];
      // The largest over the facet's vertices, as in assemble: no vertex is cut off.
      plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[loop[q]].point));
    }
  }
  out.V = V, out.E = E, out.F = nf;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Fast;
  return true;
}

}  // namespace minksum::detail
