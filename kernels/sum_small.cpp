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
// iff exactly one of its two face normals has d_A . N > 0. With P[g] the set of A's edges with
// d_A . N_g > 0 (a bit set per face g of B) and Q[f] the same for B's edges and A's faces, the
// A edges whose circles cross arc e_B are P[L'] ^ P[R'] (its faces L', R'), and the B edges
// whose circles cross arc e_A are Q[L] ^ Q[R]; Gregorius's hemisphere condition (GDC 2013; the
// signs of sum_fast.cpp's crossing_facet) then decides the crossing.
// The same bits give the supports: along a face normal N of the other operand, an operand's
// edges point up (bit set) or down, and its support vertex is the one vertex all of whose edges
// point to it (a linear function has one local maximum on a convex polytope's graph); the
// support_sinks kernel finds it. The crossings on arc e_A are then found by walking B's
// support from one end of the arc to the other (see the loop), one test per crossing.
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

constexpr int kMax = 64;            // vertices, faces and edges per operand (one bit each)
constexpr int kMaxCrossings = 192;  // parallelogram facets (more: the general path)
using Mask = std::uint64_t;

// One operand by component (the layout of the edge_signs kernel, zero-padded to 8): face
// normals and edge directions; per vertex, its edges and those of them that end there.
struct Operand {
  int V, F, E;
  double normal[3][kMax], dir[3][kMax];
  int first[kMax];  // per face, where its loop has its smallest vertex (output loops start there)
  int steps;        // the faces' loop lengths summed
  Mask edges[kMax], ends[kMax];
};

// False when the operand is too large, flat, or its edges are not oriented as documented.
bool prepare(const ConvexPolytope& p, Operand& o) {
  o.V = int(p.vertices.size()), o.F = int(p.faces.size()), o.E = int(p.edges.size());
  if (p.flat || o.V > kMax || o.F > kMax || o.E > kMax) return false;
  // (Padded to a multiple of 8 for support_sinks: no edges, and ends no mask matches.)
  const int padded = (o.V + 7) / 8 * 8;
  std::fill(o.edges, o.edges + padded, 0), std::fill(o.ends, o.ends + o.V, 0);
  std::fill(o.ends + o.V, o.ends + padded, ~Mask(0));
  o.steps = 0;
  for (int f = 0; f < o.F; ++f) {
    const auto& face = p.faces[f];
    // Unit normals (as the polytope builders make them) serve as the facets' own.
    if (!(std::abs(face.normal.squaredNorm() - 1) <= 1e-14)) return false;
    for (int c = 0; c < 3; ++c) o.normal[c][f] = face.normal[c];
    o.first[f] = int(std::min_element(face.loop.begin(), face.loop.end()) - face.loop.begin());
    o.steps += int(face.loop.size());
  }
  // The face normals read back from the copies above, not from the faces.
  const auto normal = [&o](int f) { return Vector3d(o.normal[0][f], o.normal[1][f], o.normal[2][f]); };
  for (int e = 0; e < o.E; ++e) {
    const Edge& ed = p.edges[e];
    const Vector3d d = p.vertices[ed.v1] - p.vertices[ed.v0];
    for (int c = 0; c < 3; ++c) o.dir[c][e] = d[c];
    o.edges[ed.v0] |= Mask(1) << e, o.edges[ed.v1] |= Mask(1) << e, o.ends[ed.v1] |= Mask(1) << e;
    if (d.dot(normal(ed.left).cross(normal(ed.right))) <= 0) return false;
  }
  for (auto& row : o.dir) std::fill(row + o.E, row + std::min(kMax, (o.E + 7) / 8 * 8), 0.0);
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

  // P[g]: A's edges with d_A . N_g > 0 for B's faces g; Q[f]: B's edges with d_B . N_f > 0.
  Mask P[kMax], Q[kMax];
  bool unsure_p, unsure_q;
  edge_signs(B.normal[0], B.normal[1], B.normal[2], B.F, A.dir[0], A.dir[1], A.dir[2], A.E, tol, P, &unsure_p);
  edge_signs(A.normal[0], A.normal[1], A.normal[2], A.F, B.dir[0], B.dir[1], B.dir[2], B.E, tol, Q, &unsure_q);
  // Supports: per face of one operand, the other's vertex highest along its normal. With every
  // edge sign beyond the margin, no other vertex comes within it of the top.
  int support_in_a[kMax], support_in_b[kMax];
  if (unsure_p || unsure_q || !support_sinks(P, B.F, A.edges, A.ends, A.V, support_in_a) ||
      !support_sinks(Q, A.F, B.edges, B.ends, B.V, support_in_b))
    return false;

  // The crossings, as (e_A, e_B, s1) with s1 = sign(d_A . N_B,left) > 0, found by walking each
  // arc e_A from N_L to N_R: B's support moves from top(L) to top(R) one vertex at a time, never
  // back (the support of B's projection onto the arc's plane, as the direction turns by less
  // than pi), and each move crosses the arc of the B edge it takes. From a vertex, the next move
  // is along the one other edge whose arc crosses e_A's: its circle separates N_L and N_R, arc
  // e_B crosses e_A's circle, and not at the antipode (s1 agrees with s4 = sign(d_B . N_A,right)).
  struct Crossing {
    int ea, eb;
    bool up;
  };
  Crossing crossings[kMaxCrossings];
  int nc = 0;
  for (int ea = 0; ea < A.E; ++ea) {
    const Edge& x = a.edges[ea];
    Mask circles = Q[x.left] ^ Q[x.right];  // B edges whose circles cross arc e_A, not yet taken
    const Mask s4 = Q[x.right];
    for (int u = support_in_b[x.left], w = support_in_b[x.right], moves = 0; u != w; ++moves) {
      if (moves == B.V || nc == kMaxCrossings) return false;
      int eb = -1;
      bool up = false;
      for (Mask m = B.edges[u] & circles; m; m &= m - 1) {
        const int e = lowest_bit(m);
        const Edge& y = b.edges[e];
        up = P[y.left] >> ea & 1;
        if (((P[y.left] ^ P[y.right]) >> ea & 1) && up == bool(s4 >> e & 1)) {
          eb = e;
          break;
        }
      }
      if (eb < 0) return false;  // no way on: not a convex polytope
      crossings[nc++] = {ea, eb, up};
      circles &= ~(Mask(1) << eb);
      u = b.edges[eb].v0 == u ? b.edges[eb].v1 : b.edges[eb].v0;
    }
  }

  // Vertices: the pairs (i, j) of the facets, in (i, j) order.
  Mask used[kMax];  // used[i] bit j: pair (i, j) is a vertex of the sum
  std::fill(used, used + A.V, 0);
  for (int f = 0; f < A.F; ++f)
    for (int i : a.faces[f].loop) used[i] |= Mask(1) << support_in_b[f];
  for (int g = 0; g < B.F; ++g) {
    Mask row = 0;
    for (int j : b.faces[g].loop) row |= Mask(1) << j;
    used[support_in_a[g]] |= row;
  }
  for (int k = 0; k < nc; ++k) {
    const Edge &x = a.edges[crossings[k].ea], &y = b.edges[crossings[k].eb];
    used[x.v0] |= Mask(1) << y.v0 | Mask(1) << y.v1;
    used[x.v1] |= Mask(1) << y.v0 | Mask(1) << y.v1;
  }
  // A closed polytope with F facets and E edges (half its loop steps) has V = 2 + E - F
  // vertices (Euler): the pairs found must be exactly that many.
  const int F = A.F + B.F + nc, steps = A.steps + B.steps + 4 * nc, V = 2 + steps / 2 - F;
  if (steps % 2 != 0 || V < 4) return false;
  out.vertices.resize(V);
  std::uint16_t number[kMax * kMax];  // pair (i, j) at i |B| + j: dense for small operands
  int v = 0;
  for (int i = 0; i < A.V; ++i)
    for (Mask m = used[i]; m; m &= m - 1, ++v) {
      if (v == V) return false;
      const int j = lowest_bit(m);
      number[i * B.V + j] = std::uint16_t(v);
      out.vertices[v] = SumVertex{i, j, a.vertices[i] + b.vertices[j]};
    }
  if (v != V) return false;

  // Facets: A's faces, B's faces, the parallelograms; each loop from its smallest pair, each
  // offset n . (a_i + b_j) at that pair, a support pair of n: h_A(n) + h_B(n), the paper's
  // support planes (the facet's other vertices lie on it to rounding, not the largest of them
  // as in assemble: a loop over them cost a tenth of the time here).
  out.planes.resize(F), out.facets.resize(F);
  const auto facet = [&](int k, const Vector3d& n, int size, auto&& vertex) {
    std::vector<int>& loop = out.facets[k];
    loop.resize(size);
    for (int q = 0; q < size; ++q) loop[q] = vertex(q);
    const SumVertex& first = out.vertices[loop[0]];
    SumPlane& plane = out.planes[k];
    plane.normal = n, plane.offset = n.dot(first.point), plane.i = first.i, plane.j = first.j;
  };
  for (int f = 0; f < A.F; ++f) {
    const auto& l = a.faces[f].loop;
    const int s = A.first[f], n = int(l.size()), j = support_in_b[f];
    facet(f, a.faces[f].normal, n, [&](int q) { return number[l[s + q < n ? s + q : s + q - n] * B.V + j]; });
  }
  for (int g = 0; g < B.F; ++g) {
    const auto& l = b.faces[g].loop;
    const int s = B.first[g], n = int(l.size()), i = support_in_a[g];
    facet(A.F + g, b.faces[g].normal, n, [&](int q) { return number[i * B.V + l[s + q < n ? s + q : s + q - n]]; });
  }
  for (int k = 0; k < nc; ++k) {
    const Edge &x = a.edges[crossings[k].ea], &y = b.edges[crossings[k].eb];
    // The normal is +-(d_A x d_B) = +-c at the crossing point X = a N_L' + b N_R' (a, b > 0) on
    // B's arc, where N_L' x X runs along d_B (B's loops are counter-clockwise); with
    // N_L' . (c x d_B) = -|d_B|^2 (d_A . N_L'), that makes X = -s1 c / |c|. Nearly parallel
    // edges: the general path (its normal from the crossing point).
    const int ea = crossings[k].ea, eb = crossings[k].eb;
    const Vector3d da(A.dir[0][ea], A.dir[1][ea], A.dir[2][ea]), db(B.dir[0][eb], B.dir[1][eb], B.dir[2][eb]);
    const Vector3d c = da.cross(db);
    const double c2 = c.squaredNorm();
    if (!(c2 > 1e-8 * da.squaredNorm() * db.squaredNorm())) return false;
    const Vector3d n = c * ((crossings[k].up ? -1 : 1) / std::sqrt(c2));
    // The cell order of crossing_facet: (v1, p) (v1, q) (v0, q) (v0, p) with p, q = w0, w1
    // for s2 = -s1 > 0 and w1, w0 for s2 < 0, started at its smallest pair.
    const int p = crossings[k].up ? y.v1 : y.v0, q = crossings[k].up ? y.v0 : y.v1;
    const int order[4] = {number[x.v1 * B.V + p], number[x.v1 * B.V + q], number[x.v0 * B.V + q], number[x.v0 * B.V + p]};
    const int s = x.v1 < x.v0 ? (p < q ? 0 : 1) : (q < p ? 2 : 3);
    facet(A.F + B.F + k, n, 4, [&](int r) { return order[(s + r) & 3]; });
  }
  out.V = V, out.E = steps / 2, out.F = F;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Fast;
  return true;
}

}  // namespace minksum::detail
