// The fast path: A (+) B from the overlay of the two Gauss maps, without a hull.
//
// Every facet normal of the sum is a vertex of the overlay of the Gauss maps of A and B: a face
// normal of A, a face normal of B, or a crossing of an edge arc of A with one of B (Barki et al.
// 2009; Fogel & Halperin 2007). Its facet is F_A(n) (+) F_B(n), the sum of the support features,
// and its vertex loop is the sequence of overlay cells (pairs (i, j)) around n. Arc crossings use
// Gregorius's test (GDC 2013, "IsMinkowskiFace"). All decisions are signs of the one predicate
// orient(p, q, r) = p . (q x r) on the stored unit normals, evaluated exactly (predicates.hpp),
// so the combinatorics are consistent; the tie rule is "strict": arcs that only touch, or a normal
// that lies exactly on an arc or on another normal, merge facets instead of creating slivers.
#include <algorithm>
#include <cmath>

#include <minksum/kernels.hpp>

#include "predicates.hpp"
#include "sum_internal.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

// Compressed incidence lists (arcs of each face, arcs of each cell): two flat arrays.
struct Incidence {
  std::vector<int> start, list;
  // Builds the lists of n owners from (owner, arc) pairs.
  void build(int n, const std::vector<std::pair<int, int>>& pairs) {
    start.assign(n + 1, 0);
    for (const auto& p : pairs) ++start[p.first + 1];
    for (int k = 0; k < n; ++k) start[k + 1] += start[k];
    list.resize(pairs.size());
    std::vector<int> fill(start.begin(), start.end() - 1);
    for (const auto& p : pairs) list[fill[p.first]++] = p.second;
  }
  const int* begin(int k) const { return list.data() + start[k]; }
  const int* end(int k) const { return list.data() + start[k + 1]; }
};

// The Gauss map of a polytope: face normals (points on the sphere), edge arcs between the
// normals of their two faces, and vertex cells bounded by arcs. A flat polygon is treated as
// the limit of a thin prism: each side gets a virtual face normal o_k in the polygon's plane and
// each vertex two cells (top, bottom) with the same coordinates; all its arcs are then < 180 deg.
struct GaussMap {
  struct Arc {
    int u, v;  // cells on either side: u where n.(p_v - p_u) < 0, v where > 0
    int L, R;  // faces at the ends: L's loop walks u -> v
  };
  std::vector<Vector3d> normal;             // per face
  Incidence face_arcs;                      // per face
  std::vector<Arc> arcs;
  std::vector<Cross> great;                 // per arc: N[L] x N[R], the arc's great circle
  std::vector<int> vertex;                  // cell -> polytope vertex
  Incidence cell_arcs;                      // per cell
  std::vector<Vector3d> point;              // per cell
};

GaussMap gauss_map(const ConvexPolytope& p) {
  GaussMap g;
  // Sizes are known up front (a flat polygon's prism: K + 2 faces, 3K arcs, 2K cells).
  const size_t K = p.flat ? p.faces[0].loop.size() : 0;
  g.normal.reserve(p.flat ? K + 2 : p.faces.size());
  g.arcs.reserve(p.flat ? 3 * K : p.edges.size());
  g.vertex.reserve(p.flat ? 2 * K : p.vertices.size());
  if (!p.flat) {
    for (const auto& f : p.faces) g.normal.push_back(f.normal);
    for (const auto& e : p.edges) g.arcs.push_back({e.v0, e.v1, e.left, e.right});
    for (int v = 0; v < int(p.vertices.size()); ++v) g.vertex.push_back(v);
  } else {
    const auto& top = p.faces[0].loop;
    const int K = int(top.size());
    const Vector3d n = p.faces[0].normal;
    g.normal = {n, -n};
    for (int k = 0; k < K; ++k) {
      const Vector3d d = p.vertices[top[(k + 1) % K]] - p.vertices[top[k]];
      g.normal.push_back(d.cross(n).normalized());  // outward side normal o_k
    }
    // Cells: k is the top copy of top[k], K + k its bottom copy. Side k's loop is
    // top(k+1) -> top(k) -> bottom(k) -> bottom(k+1), which fixes the arcs' orientation.
    for (int k = 0; k < K; ++k) {
      const int k1 = (k + 1) % K, side = 2 + k, prev_side = 2 + (k + K - 1) % K;
      g.arcs.push_back({k, k1, 0, side});               // top face edge
      g.arcs.push_back({K + k1, K + k, 1, side});       // bottom face edge
      g.arcs.push_back({k, K + k, side, prev_side});    // zero-length edge at vertex top[k]
    }
    for (int c = 0; c < 2 * K; ++c) g.vertex.push_back(top[c % K]);
  }
  std::vector<std::pair<int, int>> by_face, by_cell;
  by_face.reserve(2 * g.arcs.size()), by_cell.reserve(2 * g.arcs.size());
  g.great.reserve(g.arcs.size());
  g.point.reserve(g.vertex.size());
  for (int e = 0; e < int(g.arcs.size()); ++e) {
    const auto& a = g.arcs[e];
    by_face.insert(by_face.end(), {{a.L, e}, {a.R, e}});
    by_cell.insert(by_cell.end(), {{a.u, e}, {a.v, e}});
    g.great.push_back(make_cross(g.normal[a.L], g.normal[a.R]));
  }
  g.face_arcs.build(int(g.normal.size()), by_face);
  g.cell_arcs.build(int(g.vertex.size()), by_cell);
  for (int v : g.vertex) g.point.push_back(p.vertices[v]);
  return g;
}

// Where a direction lies in a Gauss map: inside a cell, inside an arc, or on a face normal.
struct Feature {
  enum Kind { Cell, Arc, Face } kind;
  int id;
};

// Classifies n against cell c: true with the feature if n is in the closed cell, false with
// an arc across which n lies (the walk continues there).
bool classify(const GaussMap& g, const Vector3d& n, int c, Feature& f, int& exit_arc) {
  int zeros[2] = {-1, -1}, nzero = 0;
  for (const int* e_it = g.cell_arcs.begin(c); e_it != g.cell_arcs.end(c); ++e_it) {
    const int e = *e_it;
    // orient(n, N_L, N_R) > 0 puts n on the v side of the arc's great circle.
    const int s = orient(n, g.great[e]) * (g.arcs[e].v == c ? 1 : -1);
    if (s < 0) return exit_arc = e, false;
    if (s == 0 && nzero < 2) zeros[nzero++] = e;
  }
  if (nzero == 0) {
    f = {Feature::Cell, c};
  } else if (nzero == 1) {
    f = {Feature::Arc, zeros[0]};
  } else {  // on two arcs of the cell: at their common face normal
    const auto &a0 = g.arcs[zeros[0]], &a1 = g.arcs[zeros[1]];
    f = {Feature::Face, (a0.L == a1.L || a0.L == a1.R) ? a0.L : a0.R};
  }
  return true;
}

// The cell of the support vertex of g in each of the normals `dirs`: the separable support
// h_(A+B)(n) = h_A(n) + h_B(n) needs |B| dot products per normal of A, done by the SIMD
// support-push kernel (all normals at once) over g's cell points in structure of arrays.
std::vector<int> support_cells(const GaussMap& g, const std::vector<Vector3d>& dirs) {
  const int n = int(g.point.size()), k = int(dirs.size());
  std::vector<double> soa(3 * n + 3 * k), best(k);
  for (int c = 0; c < n; ++c)
    for (int d = 0; d < 3; ++d) soa[d * n + c] = g.point[c][d];
  double* dir = soa.data() + 3 * n;
  for (int q = 0; q < k; ++q)
    for (int d = 0; d < 3; ++d) dir[d * k + q] = dirs[q][d];
  std::vector<int> cells(k);
  support_push(soa.data(), soa.data() + n, soa.data() + 2 * n, n, dir, dir + k, dir + 2 * k, k,
               best.data(), cells.data());
  return cells;
}

// Locates n by walking from the support cell c across the arcs n lies beyond.
bool locate(const GaussMap& g, const Vector3d& n, int c, Feature& f) {
  int exit_arc = -1;
  for (size_t step = 0; step <= g.point.size(); ++step) {
    if (classify(g, n, c, f, exit_arc)) return true;
    const auto& a = g.arcs[exit_arc];
    c = (a.u == c) ? a.v : a.u;
  }
  for (c = 0; c < int(g.point.size()); ++c)  // the walk cycled: only bad input gets here
    if (classify(g, n, c, f, exit_arc)) return true;
  return false;
}

// A direction leaving the facet normal n along an arc towards normal m; `after` is the cell
// counter-clockwise after it (seen from outside).
struct Dir {
  Vector3d m;
  int after;
  bool from_a;
};

void directions(const GaussMap& g, const Feature& f, bool from_a, std::vector<Dir>& out) {
  auto add = [&](int e, bool towards_R) {
    const auto& a = g.arcs[e];
    // Walking towards R, cell v is on the left (counter-clockwise) side; towards L, cell u.
    out.push_back(towards_R ? Dir{g.normal[a.R], a.v, from_a} : Dir{g.normal[a.L], a.u, from_a});
  };
  if (f.kind == Feature::Face)
    for (const int* e = g.face_arcs.begin(f.id); e != g.face_arcs.end(f.id); ++e)
      add(*e, g.arcs[*e].L == f.id);
  if (f.kind == Feature::Arc) add(f.id, true), add(f.id, false);
}

// Facet loop at the overlay vertex n (a face normal of A or B): the cells around n in
// counter-clockwise order; directions that coincide are one boundary (merged facets).
// Scratch buffers of sector_loop, kept across the facets of one sum (no allocation per facet).
struct SectorScratch {
  std::vector<Dir> dirs;
  std::vector<std::pair<int, Dir>> keyed;
};

FacetLoop sector_loop(const GaussMap& ga, const Feature& fa, const GaussMap& gb,
                      const Feature& fb, const Vector3d& n, SectorScratch& scratch) {
  auto& dirs = scratch.dirs;
  dirs.clear();
  directions(ga, fa, true, dirs);
  directions(gb, fb, false, dirs);
  const Vector3d ref = dirs[0].m;
  auto tangent = [&](const Vector3d& m) { return Vector3d(m - n.dot(m) * n); };
  // Angle classes about n from ref: 0 = ref's direction, 1 = (0, 180), 2 = 180, 3 = (180, 360).
  auto angle_class = [&](const Vector3d& m) {
    const int s = orient(n, ref, m);
    if (s != 0) return s > 0 ? 1 : 3;
    return tangent(ref).dot(tangent(m)) > 0 ? 0 : 2;
  };
  auto& keyed = scratch.keyed;
  keyed.clear();
  for (const auto& d : dirs) keyed.emplace_back(angle_class(d.m), d);
  auto same = [&](const auto& x, const auto& y) {
    return x.first == y.first && (x.first % 2 == 0 || orient(n, x.second.m, y.second.m) == 0);
  };
  std::sort(keyed.begin(), keyed.end(), [&](const auto& x, const auto& y) {
    if (x.first != y.first) return x.first < y.first;
    return x.first % 2 == 1 && orient(n, x.second.m, y.second.m) > 0;
  });
  // The cell before the first direction is the one after the last direction of each map.
  int ca = fa.kind == Feature::Cell ? fa.id : -1, cb = fb.kind == Feature::Cell ? fb.id : -1;
  for (const auto& [cls, d] : keyed) (d.from_a ? ca : cb) = d.after;
  FacetLoop f{n, {}};
  for (size_t k = 0; k < keyed.size(); ++k) {
    const Dir& d = keyed[k].second;
    (d.from_a ? ca : cb) = d.after;
    if (k + 1 < keyed.size() && same(keyed[k], keyed[k + 1])) continue;  // one merged boundary
    f.loop.emplace_back(ga.vertex[ca], gb.vertex[cb]);
  }
  return f;
}

// Gregorius's arc-crossing test with strict signs: a facet iff the arcs cross at inner points.
// On success, fills the parallelogram facet e_A (+) e_B.
// side[f][e]: the sign of orient(normal f of one map, great circle of arc e of the other),
// computed once per (normal, arc) instead of once per pair of arcs.
struct Sides {
  int arcs;
  std::vector<signed char> sign;
  Sides(const GaussMap& normals, const GaussMap& circles) : arcs(int(circles.arcs.size())) {
    sign.resize(normals.normal.size() * circles.arcs.size());
    for (size_t f = 0; f < normals.normal.size(); ++f)
      for (int e = 0; e < arcs; ++e) sign[f * arcs + e] = static_cast<signed char>(orient(normals.normal[f], circles.great[e]));
  }
  int operator()(int f, int e) const { return sign[size_t(f) * arcs + e]; }
};

bool crossing_facet(const GaussMap& ga, int ea, const GaussMap& gb, int eb, const Sides& b_vs_a,
                    const Sides& a_vs_b, FacetLoop& f) {
  const auto &A = ga.arcs[ea], &B = gb.arcs[eb];
  const Vector3d &a1 = ga.normal[A.L], &a2 = ga.normal[A.R];
  const int s1 = b_vs_a(B.L, ea), s2 = b_vs_a(B.R, ea);
  if (s1 * s2 >= 0) return false;
  const int s3 = a_vs_b(A.L, eb), s4 = a_vs_b(A.R, eb);
  if (s3 * s4 >= 0 || s1 * s4 <= 0) return false;
  // The facet is the parallelogram e_A (+) e_B, so its normal is +-(d_A x d_B). The crossing
  // point p = |a2.g_B| a1 + |a1.g_B| a2 always lies on A's arc and fixes the sign; it is the
  // normal itself only when the edges are too close to parallel for the cross product.
  const Vector3d& gB = gb.great[eb].value;
  const Vector3d p = std::abs(a2.dot(gB)) * a1 + std::abs(a1.dot(gB)) * a2;
  const Vector3d dA = ga.point[A.v] - ga.point[A.u], dB = gb.point[B.v] - gb.point[B.u];
  const Vector3d c = dA.cross(dB);
  if (c.norm() > 1e-12 * dA.norm() * dB.norm())
    f.normal = c.dot(p) >= 0 ? c.normalized() : Vector3d(-c.normalized());
  else
    f.normal = p.norm() > 0 ? p.normalized() : Vector3d((a1 + a2).normalized());
  // s2 > 0: b2 is on the v side of A's circle, so B's direction towards b2 follows A's
  // direction towards a2 counter-clockwise; the four cells follow from that order.
  const int uA = ga.vertex[A.u], vA = ga.vertex[A.v], uB = gb.vertex[B.u], vB = gb.vertex[B.v];
  if (s2 > 0)
    f.loop = {{vA, uB}, {vA, vB}, {uA, vB}, {uA, uB}};
  else
    f.loop = {{vA, vB}, {vA, uB}, {uA, uB}, {uA, vB}};
  return true;
}

}  // namespace

bool sum_fast(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out) {
  const GaussMap ga = gauss_map(a), gb = gauss_map(b);
  std::vector<FacetLoop> facets;
  facets.reserve(ga.normal.size() + gb.normal.size() + ga.arcs.size());
  SectorScratch scratch;
  Feature fa, fb;
  const std::vector<int> start_b = support_cells(gb, ga.normal);
  const std::vector<int> start_a = support_cells(ga, gb.normal);
  // Face normals of A: F_A(n) is the face, F_B(n) is wherever n lies in B's Gauss map.
  for (int f = 0; f < int(ga.normal.size()); ++f) {
    if (!locate(gb, ga.normal[f], start_b[f], fb)) return false;
    facets.push_back(sector_loop(ga, {Feature::Face, f}, gb, fb, ga.normal[f], scratch));
  }
  // Face normals of B, except those that coincide with a face normal of A (done above).
  for (int f = 0; f < int(gb.normal.size()); ++f) {
    if (!locate(ga, gb.normal[f], start_a[f], fa)) return false;
    if (fa.kind != Feature::Face)
      facets.push_back(sector_loop(ga, fa, gb, {Feature::Face, f}, gb.normal[f], scratch));
  }
  // Edge-edge facets: every crossing of an arc of A with an arc of B.
  const Sides b_vs_a(gb, ga), a_vs_b(ga, gb);
  FacetLoop f;
  for (int ea = 0; ea < int(ga.arcs.size()); ++ea)
    for (int eb = 0; eb < int(gb.arcs.size()); ++eb)
      if (crossing_facet(ga, ea, gb, eb, b_vs_a, a_vs_b, f)) facets.push_back(f);
  assemble(a, b, facets, out);
  return true;
}

}  // namespace minksum::detail
