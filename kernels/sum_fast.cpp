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

// Locates n by walking from cell c across the arcs n lies beyond: hill climbing on the
// polytope's vertices along n (each step raises n . p), so it ends, at the support.
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

// Locates every face normal of `from` in g, walking from where a neighbouring face's normal
// was found (a few steps), in breadth-first order over the faces: linear in the sizes rather
// than |from| |g| support evaluations. The first walk starts at the support vertex.
bool locate_all(const GaussMap& from, const GaussMap& g, std::vector<Feature>& out) {
  const int F = int(from.normal.size());
  out.assign(F, Feature{Feature::Cell, -1});
  int top = 0;
  for (int c = 1; c < int(g.point.size()); ++c)
    if (from.normal[0].dot(g.point[c]) > from.normal[0].dot(g.point[top])) top = c;
  std::vector<int> queue = {0}, start(F, -1);
  start[0] = top;
  for (size_t k = 0; k < queue.size(); ++k) {
    const int f = queue[k];
    if (!locate(g, from.normal[f], start[f], out[f])) return false;
    // A cell of the feature found: where the neighbours' walks begin.
    const Feature& x = out[f];
    const int cell = x.kind == Feature::Cell ? x.id
                     : x.kind == Feature::Arc ? g.arcs[x.id].u
                                              : g.arcs[*g.face_arcs.begin(x.id)].u;
    for (const int* e = from.face_arcs.begin(f); e != from.face_arcs.end(f); ++e) {
      const int next = from.arcs[*e].L == f ? from.arcs[*e].R : from.arcs[*e].L;
      if (start[next] < 0) start[next] = cell, queue.push_back(next);
    }
  }
  return int(queue.size()) == F;
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
bool crossing_facet(const GaussMap& ga, int ea, const GaussMap& gb, int eb, FacetLoop& f) {
  const auto &A = ga.arcs[ea], &B = gb.arcs[eb];
  const Vector3d &a1 = ga.normal[A.L], &a2 = ga.normal[A.R];
  const int s1 = orient(gb.normal[B.L], ga.great[ea]), s2 = orient(gb.normal[B.R], ga.great[ea]);
  if (s1 * s2 >= 0) return false;
  const int s3 = orient(a1, gb.great[eb]), s4 = orient(a2, gb.great[eb]);
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

// A uniform grid over [-1, 1]^3 holding each arc in every cell its bounding box meets. Two arcs
// that cross share a point, so their boxes share a cell: testing the pairs that share a cell
// (each pair once: in the lowest cell of the two boxes' overlap) finds every crossing, in time
// about linear in the arcs and the crossings for arcs short against the sphere.
struct ArcGrid {
  struct Range {
    int lo[3], hi[3];
  };
  int n = 1;  // cells per axis
  std::vector<Range> ra, rb;
  Incidence cells_b;  // per cell: the arcs of B in it

  // The arc from p to q (< 180 deg) lies in the triangle of p, q and the meeting point of its
  // end tangents, (p + q) / (1 + p . q), and on the unit sphere: the box of both, padded.
  Range range(const Vector3d& p, const Vector3d& q) const {
    const double c = 1 + p.dot(q);
    Vector3d lo = p.cwiseMin(q), hi = p.cwiseMax(q);
    if (c > 1e-6) {
      const Vector3d t = (p + q) / c;
      lo = lo.cwiseMin(t), hi = hi.cwiseMax(t);
    } else {  // nearly antipodal ends (not on a valid polytope): anywhere
      lo.setConstant(-1), hi.setConstant(1);
    }
    Range r;
    for (int d = 0; d < 3; ++d) {
      r.lo[d] = std::clamp(int(std::floor((lo[d] - 1e-9 + 1) / 2 * n)), 0, n - 1);
      r.hi[d] = std::clamp(int(std::floor((hi[d] + 1e-9 + 1) / 2 * n)), 0, n - 1);
    }
    return r;
  }

  void build(const GaussMap& ga, const GaussMap& gb) {
    // About one arc of each map per cell the arcs occupy (a band of ~6 n^2 cells); one cell
    // (every pair) while there are few pairs.
    const double arcs = double(ga.arcs.size() + gb.arcs.size());
    n = double(ga.arcs.size()) * double(gb.arcs.size()) <= 256 ? 1 : std::max(1, int(std::sqrt(arcs / 6)));
    for (auto [g, r] : {std::pair{&ga, &ra}, std::pair{&gb, &rb}}) {
      r->clear();
      for (const auto& a : g->arcs) r->push_back(range(g->normal[a.L], g->normal[a.R]));
    }
    std::vector<std::pair<int, int>> in;
    for (int e = 0; e < int(rb.size()); ++e)
      for (int x = rb[e].lo[0]; x <= rb[e].hi[0]; ++x)
        for (int y = rb[e].lo[1]; y <= rb[e].hi[1]; ++y)
          for (int z = rb[e].lo[2]; z <= rb[e].hi[2]; ++z) in.emplace_back((x * n + y) * n + z, e);
    cells_b.build(n * n * n, in);
  }

  template <class F>
  void for_each_pair(F&& f) const {
    for (int ea = 0; ea < int(ra.size()); ++ea) {
      const Range& a = ra[ea];
      for (int x = a.lo[0]; x <= a.hi[0]; ++x)
        for (int y = a.lo[1]; y <= a.hi[1]; ++y)
          for (int z = a.lo[2]; z <= a.hi[2]; ++z)
            for (const int* e = cells_b.begin((x * n + y) * n + z); e != cells_b.end((x * n + y) * n + z); ++e) {
              const Range& b = rb[*e];
              if (x == std::max(a.lo[0], b.lo[0]) && y == std::max(a.lo[1], b.lo[1]) &&
                  z == std::max(a.lo[2], b.lo[2]))
                f(ea, *e);
            }
    }
  }
};

}  // namespace

bool sum_fast(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out) {
  const GaussMap ga = gauss_map(a), gb = gauss_map(b);
  std::vector<FacetLoop> facets;
  facets.reserve(ga.normal.size() + gb.normal.size() + ga.arcs.size());
  SectorScratch scratch;
  std::vector<Feature> in_b, in_a;
  if (!locate_all(ga, gb, in_b) || !locate_all(gb, ga, in_a)) return false;
  // Face normals of A: F_A(n) is the face, F_B(n) is wherever n lies in B's Gauss map.
  for (int f = 0; f < int(ga.normal.size()); ++f)
    facets.push_back(sector_loop(ga, {Feature::Face, f}, gb, in_b[f], ga.normal[f], scratch));
  // Face normals of B, except those that coincide with a face normal of A (done above).
  for (int f = 0; f < int(gb.normal.size()); ++f)
    if (in_a[f].kind != Feature::Face)
      facets.push_back(sector_loop(ga, in_a[f], gb, {Feature::Face, f}, gb.normal[f], scratch));
  // Edge-edge facets: every crossing of an arc of A with an arc of B, tested only for arcs
  // that share a cell of the grid (output-sensitive rather than |E_A| |E_B|).
  FacetLoop f;
  ArcGrid grid;
  grid.build(ga, gb);
  grid.for_each_pair([&](int ea, int eb) {
    if (crossing_facet(ga, ea, gb, eb, f)) facets.push_back(f);
  });
  assemble(a, b, facets, out);
  return true;
}

}  // namespace minksum::detail
