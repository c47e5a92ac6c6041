// A (+) B of two placed shapes by overlaying their Gauss maps exactly, output-sensitively, for
// operands of any size (Barki, Denis & Dupont 2009; Fogel & Halperin 2007; arc crossings after
// Gregorius, GDC 2013).
//
// The facets of A (+) B are the vertices of the overlay of the two Gauss maps:
//  - each face normal N of A, with facet F_A(N) (+) F_B(N): the face plus the support feature
//    of B along N (a vertex; an edge or a face where N lies on B's arcs: merged facets);
//  - likewise each face normal of B that is not also one of A;
//  - each proper crossing of an arc e_A with an arc e_B: the parallelogram e_A (+) e_B.
// Arc e lies on the great circle of pole c = G_L x G_R (a positive multiple of its edge), so the
// side of it a normal G lies on is the sign of det(G, G_L, G_R). The Gauss normals G are the
// faces' exact Newell normals (shape_data.hpp): a canonical double vector where the normal is
// one (so parallel faces of two shapes have the same vector), else a rounded vector plus the
// exact normal's expansions (rounded coordinates: cos/sin prisms, decimals). Every sign is the
// exact one, zero included: a double evaluation decides it when it clears kSideFilter (a static
// filter, Shewchuk 1997, that also covers a rounded normal's own rounding), exact expansions on
// the stack when it does not (predicates.hpp). The overlay computed is therefore the exact
// overlay of the two maps, ties and all; no perturbation and no rational arithmetic. (A map
// turned against A's, B's under a rotation, is the exact overlay of its turned normals.)
//
// The algorithm (O(|E_A| + |E_B| + output) after one linear scan for the first support):
//  1. Every arc of A is walked through B's map, breadth first over A's faces from the first,
//     whose normal is located by climbing from B's best vertex (each step raises B's support
//     along it). In a cell, the walk leaves where the cell's corners, read counter-clockwise,
//     pass from the right of the arc's circle to its left: across a side (a proper crossing, a
//     parallelogram facet) or through a corner (a face normal of B on the arc); from a corner
//     it goes on into the cell, or along the arc of B, that holds its direction. A walk towards
//     a normal not yet located finds it too: it has arrived when that normal is not beyond the
//     side it leaves by, one sign a step; so every normal of A ends located exactly (in a cell,
//     inside an arc or on a face normal of B: the support feature of B along it).
//  2. Every face normal of B is located in A's map: those on A's arcs and normals by the walks
//     that met them; the others from a located neighbour across their common arc, which no arc
//     of A crosses (the same cell) or one crosses (the cell across it); else by climbing.
//  3. The facets are written: a face normal inside a cell gives its face with one vertex of the
//     other operand; one on an arc or a face normal gives the merged polygon, read off the
//     rays of both maps around it (merged_facet); a crossing gives its parallelogram. Their
//     vertices, pairs (i, j), are numbered in (i, j) order (PairNumbering), the result written
//     once, and Euler's formula checked (and, where features merged under a rotation, the
//     closed manifold).
// A step that fails (only a shape whose map rounding made invalid can make one) leaves the hull
// corrector to answer.
#include <algorithm>
#include <cmath>

#include "sum/overlay.hpp"
#include "core/predicates.hpp"
#include "core/scale.hpp"
#include "sum/sum_internal.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

// Whether rounded normals a and b are within their rounding of one line (canonical vectors:
// components at most 1, each within kRoundedNormal of its exact value).
inline bool nearly_collinear(const Vector3d& a, const Vector3d& b) {
  return a.cross(b).cwiseAbs().maxCoeff() <= 10 * kRoundedNormal;
}

// Whether normal f of X and normal g of Y (of the other operand) lie exactly on one line: their
// exact terms, once per pair of faces and way (Placed::collinear: a face of A has at most one
// face of B each way near its line; the aligned prisms' ties ask the same pair many times).
bool collinear(const Placed& X, int f, const Placed& Y, int g) {
  const Placed& A = X.is_a ? X : Y;
  const int fa = X.is_a ? f : g, fb = X.is_a ? g : f;
  int& memo = A.collinear[2 * fa + (X.g[f].dot(Y.g[g]) > 0)];
  if (memo >= 0 && memo >> 1 == fb) return memo & 1;
  // (A near-tie, a face within rounding of parallel to another, is told apart to 106 bits.)
  double x[3 * kMaxGaussTerms], y[3 * kMaxGaussTerms];
  const bool on_line = !near_apart(X.near(f), Y.near(g)) && collinear_exact(X.exact(f, x), Y.exact(g, y));
  memo = 2 * fb + on_line;
  return on_line;
}

// The exact sign of det(G_p, G_q, G_r) for normals of placed shapes (Q and R one operand, P
// the other or the same): orient on the doubles where all three are exact as stored; else the
// doubles past a filter that covers their rounding; else 0 where G_p lies on the line of G_q
// or G_r (a face parallel to another: the rounded ties); else the normals to 106 bits (a
// near-tie: a face within rounding of parallel to another), kept per face for the overlay;
// else the exact terms.
int orient_normals(const Placed& P, int p, const Placed& Q, int q, const Placed& R, int r) {
  if (!P.rounded_normal(p) && !Q.rounded_normal(q) && !R.rounded_normal(r)) return orient(P.g[p], Q.g[q], R.g[r]);
  if (const int s = orient_rounded_filter(P.g[p], Q.g[q], R.g[r])) return s;
  if (P.is_a != Q.is_a && ((nearly_collinear(P.g[p], Q.g[q]) && collinear(P, p, Q, q)) ||
                           (nearly_collinear(P.g[p], R.g[r]) && collinear(P, p, R, r))))
    return 0;
  if (const int s = orient_near(P.near(p), Q.near(q), R.near(r))) return s;
  double x[3][3 * kMaxGaussTerms];
  return orient_expansions(P.exact(p, x[0]), Q.exact(q, x[1]), R.exact(r, x[2]));
}

// The exact side of X's arc e (its pole) on which Y's normal f lies: sign det(G_f, G_L, G_R):
// the filter, then a zero for want of terms (no component of G_f meets a nonzero one of the
// pole's), then the exact predicate.
inline int side(const Placed& X, int e, const Placed& Y, int f) {
  const Vector3d &c = X.c[e], &g = Y.g[f];
  const double v = c.x() * g.x() + c.y() * g.y() + c.z() * g.z();
  if (v > kSideFilter) return 1;
  if (v < -kSideFilter) return -1;
  if ((Y.g_nonzero[f] & ~X.c_zero[e]) == 0) return 0;
  return orient_normals(Y, f, X, X.L(e), X, X.R(e));
}

// Whether normal f of X and normal g of Y (the other operand) point exactly the same way: equal
// vectors where both are exact as stored; else (rounded normals, parallel or a true sliver
// apart) their exact terms.
bool same_normal(const Placed& X, int f, const Placed& Y, int g) {
  const Vector3d &a = X.g[f], &b = Y.g[g];
  if (!X.rounded_normal(f) && !Y.rounded_normal(g)) return a == b;
  return a.dot(b) > 0 && nearly_collinear(a, b) && collinear(X, f, Y, g);
}

// Whether Y's normal f lies beyond the side of X's cell at `slot` (the cell across is higher
// along it): +1, 0 on the side's circle, -1.
inline int beyond(const Placed& X, int slot_arc, const Placed& Y, int f) {
  return slot_arc >= 0 ? side(X, slot_arc, Y, f) : -side(X, ~slot_arc, Y, f);
}

using Loc = Location;

// A cell of X in the closure of a location's feature.
int some_cell(const Placed& X, const Loc& l) {
  if (l.kind == Loc::Cell) return l.id;
  if (l.kind == Loc::Arc) return X.m->arc[l.id].u;
  return X.m->loop_cell[X.m->loop_start[l.id]];
}

// The cell of X best along the normal f of Y, by a linear scan of X's placed vertices (the
// first support only; the climb from it decides exactly).
int best_cell(const Placed& X, const Placed& Y, int f) {
  const ShapeData& s = *X.s;
  const Vector3d n = Y.unit(f);
  int best = 0;
  double top = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < s.cells; ++c) {
    const int v = s.cell_vertex[c];
    const double h = n.x() * X.px[v] + n.y() * X.py[v] + n.z() * X.pz[v];
    if (h > top) top = h, best = c;
  }
  return best;
}

// The exact location of Y's normal f in X's map, climbing from `cell` across the sides it lies
// beyond (each step raises X's support along the normal); false on failure. Where no side is
// strictly beyond, the cell is a support vertex, and the sides whose circles hold the normal
// tell the feature: none, the cell; one, that arc; two (consecutive), their common face.
bool climb(const Placed& X, const Placed& Y, int f, int cell, Loc& out) {
  const MapLayout& m = *X.m;
  for (int steps = 0; steps <= X.s->cells; ++steps) {
    int zeros = 0, z[2] = {-1, -1}, next = -1;
    const int begin = m.cell_start[cell], end = m.cell_start[cell + 1];
    for (int k = begin; k < end; ++k) {
      const int b = beyond(X, m.cell_slot[k].arc, Y, f);
      if (b > 0) {
        next = m.cell_slot[k].next;
        break;
      }
      if (b == 0 && zeros++ < 2) z[zeros - 1] = k;
    }
    if (next >= 0) {
      cell = next;
      continue;
    }
    const auto arc_of = [&m](int k) { return m.cell_slot[k].arc >= 0 ? m.cell_slot[k].arc : ~m.cell_slot[k].arc; };
    if (zeros == 0) {
      out = {Loc::Cell, cell};
    } else if (zeros == 1) {
      out = {Loc::Arc, arc_of(z[0])};
    } else if (zeros == 2 && (z[1] == z[0] + 1 || (z[0] == begin && z[1] == end - 1))) {
      out = {Loc::Face, m.cell_slot[z[1] == z[0] + 1 ? z[0] : z[1]].face};  // the face between them
    } else {
      return false;
    }
    return true;
  }
  return false;
}

// Whether face R of arc e of X lies ahead of the normal `from` (inside e) along the common
// circle of e and an arc of A from `from` to `to`: two points of a great circle are on the same
// side of the plane through `from` and an axis off the circle iff they lie within the same half
// turn from it.
bool right_end_ahead(const Placed& X, int e, const Placed& A, int from, int to) {
  const Vector3d c = X.pole(e).cwiseAbs();
  const int k = c.x() >= c.y() && c.x() >= c.z() ? 0 : c.y() >= c.z() ? 1 : 2;
  const Vector3d axis = Vector3d::Unit(k);
  if (!A.rounded_normal(from) && !A.rounded_normal(to) && !X.rounded_normal(X.R(e)))
    return orient(axis, A.g[from], X.g[X.R(e)]) == orient(axis, A.g[from], A.g[to]);
  const auto turn = [&](const Placed& P, int g) {
    if (const int s = orient_rounded_filter(axis, A.g[from], P.g[g])) return s;
    double x[2][3 * kMaxGaussTerms];
    return orient_exact(exact_vector(axis), A.exact(from, x[0]), P.exact(g, x[1]));
  };
  return turn(X, X.R(e)) == turn(A, to);
}

// The other side of cell `cell` at its corner `corner`, next to the side at `slot`.
int side_beside(const MapLayout& m, int cell, int slot, int corner) {
  const int begin = m.cell_start[cell], end = m.cell_start[cell + 1];
  if (m.cell_slot[slot].face == corner) return slot + 1 < end ? slot + 1 : begin;  // corner after the side
  return slot > begin ? slot - 1 : end - 1;
}

// Where a walk leaving a face normal of B starts: into cell id, whose corner after slot `entry`
// lies right of the arc, or along arc id of B towards its face normal head.
struct WalkStart {
  bool along;
  int id, entry, head;
};

// The start of a walk leaving face normal g of B in the direction of g's ray or sector
// `sector` (place_rays: 2k + 1 along ray k, 2k + 2 strictly after it): into the cell after ray
// k, whose corner after g (across ray k + 1) lies right of the walk, or along ray k.
WalkStart start_at(const MapLayout& m, int g, int sector) {
  const int first = m.loop_start[g], n = m.loop_start[g + 1] - first, k = (sector - 1) / 2;
  if (sector % 2 == 1) return {true, m.loop_arc[first + k], -1, m.loop_face[first + k]};
  const int after = (k + 1) % n, c = m.loop_cell[first + after], s = m.loop_slot[first + after];
  return {false, c, s + 1 < m.cell_start[c + 1] ? s + 1 : m.cell_start[c], -1};
}

// Walks arc ea of A from its face `from` (at `start` in B's map; from a face normal of B, in the
// direction `ahead` if given) to its other face through B's map (step 1 of the file's comment),
// appending the proper crossings, and noting in loc_a the face normals of B it passes through
// (inside the arc). The other face's location `target` is known, or found (known false). False
// on failure.
bool walk(const Placed& A, const Placed& B, int ea, int from, const Loc& start, const WalkStart* ahead, Loc& target,
          bool known, std::vector<Crossing>& out, std::vector<Loc>& loc_a) {
  const MapLayout& m = *B.m;
  const int to = A.L(ea) == from ? A.R(ea) : A.L(ea), tsign = A.L(ea) == from ? 1 : -1;
  // The side of the arc's circle, seen along its way, on which B's normal g lies (left: +):
  // side() with the arc's pole turned the way of the walk, kept in registers.
  const Vector3d pole = double(tsign) * A.c[ea];
  const auto sigma = [&](int g) {
    const Vector3d& x = B.g[g];
    const double v = pole.x() * x.x() + pole.y() * x.y() + pole.z() * x.z();
    if (v > kSideFilter) return 1;
    if (v < -kSideFilter) return -1;
    if ((B.g_nonzero[g] & ~A.c_zero[ea]) == 0) return 0;
    return tsign * orient_normals(B, g, A, A.L(ea), A, A.R(ea));
  };
  // Whether the far end lies beyond a side of a cell (at `slot`).
  const auto past = [&](int slot) { return beyond(B, m.cell_slot[slot].arc, A, to); };
  enum { InCell, AtFace, Along } kind;
  int id = start.id, entry = -1, head = -1;  // entry: a slot of the cell whose corner lies right
  if (ahead) {                               // from a face normal of B, the way the caller placed the arc's direction
    kind = ahead->along ? Along : InCell, id = ahead->id, entry = ahead->entry, head = ahead->head;
  } else if (start.kind == Loc::Cell) {
    kind = InCell;
  } else if (start.kind == Loc::Face) {
    kind = AtFace;
  } else {  // from inside arc e of B: across it, or along it
    const MapLayout::Arc& a = m.arc[id];
    if (sigma(a.L) == 0 && sigma(a.R) == 0) {
      kind = Along, head = right_end_ahead(B, id, A, from, to) ? a.R : a.L;
    } else {
      const int s = side(B, id, A, to);  // the side of e's circle the arc goes to
      if (s == 0) return false;
      kind = InCell, entry = m.arc_slot[2 * id + (s > 0)], id = s > 0 ? a.v : a.u;
      if (sigma(m.cell_slot[entry].face) >= 0) return false;
    }
  }
  for (int steps = 0; steps <= 2 * (B.s->cells + B.s->faces); ++steps) {
    if (kind == Along) {  // along arc id of B, to its face normal head
      if (known ? target.kind == Loc::Arc && target.id == id : false) return true;
      if (!known) {  // arrived if the far end is not past the other side at head of a cell of the arc
        const int cell = m.arc[id].u, q = past(side_beside(m, cell, m.arc_slot[2 * id], head));
        if (q <= 0) return target = q < 0 ? Loc{Loc::Arc, id} : Loc{Loc::Face, head}, true;
      }
      kind = AtFace, id = head;
      if (!(known && target.kind == Loc::Face && target.id == id)) loc_a[id] = {Loc::Arc, ea};  // inside the arc
      continue;
    }
    if (kind == AtFace) {  // on face normal id of B: into the cell, or along the arc, ahead
      if (known && target.kind == Loc::Face && target.id == id) return true;
      const int first = m.loop_start[id], n = m.loop_start[id + 1] - first;
      int prev = sigma(m.loop_face[first + n - 1]), k = 0, now = 0;
      for (; k < n; ++k) {
        now = sigma(m.loop_face[first + k]);
        if (prev < 0 && now >= 0) break;
        prev = now;
      }
      if (k == n) return false;
      if (now == 0) {  // along ray k
        kind = Along, head = m.loop_face[first + k], id = m.loop_arc[first + k];
      } else {  // into cell k; its corner after `entry` (across ray k - 1) lies right
        const int s = m.loop_slot[first + k], c = m.loop_cell[first + k];
        kind = InCell, id = c, entry = s + 1 < m.cell_start[c + 1] ? s + 1 : m.cell_start[c];
      }
      continue;
    }
    // In cell id: arrived, or out across the side or through the corner ahead.
    if (known && target.kind == Loc::Cell && target.id == id) return true;
    if (known && target.kind == Loc::Arc && (m.arc[target.id].u == id || m.arc[target.id].v == id)) return true;
    const int begin = m.cell_start[id], end = m.cell_start[id + 1], n = end - begin;
    int k = -1, now = 0;
    if (entry >= 0) {  // corners after the entry, until one is not right of the circle
      for (int t = 1, s = entry; t < n; ++t) {
        s = s + 1 < end ? s + 1 : begin;
        if ((now = sigma(m.cell_slot[s].face)) >= 0) {
          k = s;
          break;
        }
      }
    } else {  // from inside: the corner where right turns to left
      int prev = sigma(m.cell_slot[end - 1].face);
      for (int s = begin; s < end; ++s) {
        now = sigma(m.cell_slot[s].face);
        if (prev < 0 && now >= 0) {
          k = s;
          break;
        }
        prev = now;
      }
    }
    if (k < 0) return false;
    if (now == 0) {  // through corner k: arrived if the far end is past neither side at it
      const int corner = m.cell_slot[k].face;
      if (!known) {
        const int q1 = past(k), q2 = past(k + 1 < end ? k + 1 : begin);
        if (q1 < 0 && q2 < 0) return target = {Loc::Cell, id}, true;
        if (q1 == 0 && q2 == 0) return target = {Loc::Face, corner}, true;
        if (q1 <= 0 && q2 <= 0) return false;
      }
      kind = AtFace, id = corner;
      if (!(known && target.kind == Loc::Face && target.id == id)) loc_a[id] = {Loc::Arc, ea};  // inside the arc
      continue;
    }
    // Across side k (between the corner before it, right, and corner k, left): arrived if the
    // far end is not past it, else a crossing.
    const int arc = m.cell_slot[k].arc, eb = arc >= 0 ? arc : ~arc;
    if (!known)
      if (const int q = past(k); q <= 0) return target = q < 0 ? Loc{Loc::Cell, id} : Loc{Loc::Arc, eb}, true;
    add_crossing(out, ea, eb, tsign * (m.arc[eb].L == m.cell_slot[k].face ? 1 : -1) > 0);
    entry = m.slot_twin[k], id = m.cell_slot[k].next;
  }
  return false;
}

// The normal of the parallelogram of two edges within 1e-4 rad of parallel, whose arcs
// (a1 -> a2, b1 -> b2, each shorter than pi) cross: the point of A's arc where B's circle
// crosses it, clamped into the part of A's arc that B's arc spans. When the edges are parallel
// to rounding the two circles coincide and the crossing point is noise, but any normal in both
// arcs supports both edges, so the clamp keeps the plane a support plane of A and of B.
Vector3d near_parallel_normal(const Vector3d& a1, const Vector3d& a2, const Vector3d& b1, const Vector3d& b2) {
  // A's arc a point (two faces whose unit normals round alike, kept apart by the exact hull):
  // the crossing is there, and no circle through it can be formed.
  if (!(a1.cross(a2).squaredNorm() > 0)) return a1;
  const Vector3d u = a1, w = a1.cross(a2).normalized().cross(a1).normalized();
  const auto angle = [&](const Vector3d& x) { return std::atan2(x.dot(w), x.dot(u)); };  // along A's circle
  const double alpha = angle(a2), kTwoPi = 2 * M_PI;
  const Vector3d gb = b1.cross(b2);
  const bool same_way = gb.dot(a1.cross(a2)) > 0;  // B's arc runs the way A's does
  const double start = angle(same_way ? b1 : b2), len = std::remainder(angle(same_way ? b2 : b1) - start, kTwoPi);
  double lo = std::max(0.0, start), hi = std::min(alpha, start + std::abs(len));
  if (start > 0 && std::min(alpha, start - kTwoPi + std::abs(len)) - std::max(0.0, start - kTwoPi) > hi - lo)
    lo = std::max(0.0, start - kTwoPi), hi = std::min(alpha, start - kTwoPi + std::abs(len));
  const Vector3d p = std::abs(a2.dot(gb)) * a1 + std::abs(a1.dot(gb)) * a2;
  double theta = p.squaredNorm() > 0 ? angle(p) : alpha / 2;
  theta = lo <= hi ? std::clamp(theta, lo, hi) : (lo + hi) / 2;
  return std::cos(theta) * u + std::sin(theta) * w;
}

// Arc e's pole_error_bound as placed (a turned map's poles are rounded from turned normals).
double pole_error(const Placed& X, int e) { return pole_error_bound(X.g[X.L(e)], X.g[X.R(e)], X.c[e]); }

// Whether the normal n (world frame, any length) can be on both crossing arcs: an arc shorter
// than pi lies within pi / 2 of its midpoint, so a normal off by a flipped sign fails.
bool on_arcs(const Placed& A, int ea, const Placed& B, int eb, const Vector3d& n) {
  return n.dot(A.unit(A.L(ea)) + A.unit(A.R(ea))) > 0 && n.dot(B.unit(B.L(eb)) + B.unit(B.R(eb))) > 0;
}

// The rays of X's feature at a facet normal, counter-clockwise: a face's arcs (each between
// two cells of its loop), or an arc's two directions.
void rays_of(const Placed& X, const Loc& f, std::vector<Overlay::Ray>& out) {
  const MapLayout& m = *X.m;
  if (f.kind == Loc::Face) {
    const int first = m.loop_start[f.id], n = m.loop_start[f.id + 1] - first;
    out.resize(size_t(n));
    for (int k = 0; k < n; ++k) out[k] = {m.loop_face[first + k], m.loop_cell[first + (k + 1 < n ? k + 1 : 0)]};
  } else {  // an arc: towards R the cell on the left is v; towards L, u
    const MapLayout::Arc& a = m.arc[f.id];
    out.resize(2);
    out[0] = {a.R, a.v}, out[1] = {a.L, a.u};
  }
}

}  // namespace

void place(const ShapeData& s, const Eigen::Isometry3d& pose, const Eigen::Matrix3d& frame, bool negate,
           PlacedBuffers& buf, Placed& out) {
  const double sign = negate ? -1.0 : 1.0;
  out.s = &s, out.m = &s.map[negate], out.negate = negate;
  out.world = Rigid(sign * pose.linear(), sign * pose.translation()), out.frame = sign * frame;
  out.own_frame = frame == Eigen::Matrix3d::Identity();
  if (out.own_frame) {  // the prepared normals and poles (-B's negated)
    if (negate) {
      buf.g.resize(s.gauss.size());
      for (size_t f = 0; f < s.gauss.size(); ++f) buf.g[f] = -s.gauss[f];
    }
    out.g = negate ? buf.g.data() : s.gauss.data(), out.g_nonzero = s.gauss_nonzero.data();
    out.c = s.pole[negate].data(), out.c_zero = s.pole_zero.data();
    out.rounded = s.any_rounded;
  } else {
    // Turned, with components below kTinyComponent zeroed (the expansions' range); the poles
    // from the turned normals themselves (not turned): the filter's bound holds against the
    // exact predicate on those normals whatever the rotation's rounding.
    const Eigen::Matrix3d& M = out.frame;
    buf.g.resize(s.gauss.size()), buf.g_nonzero.resize(s.gauss.size());
    for (size_t f = 0; f < s.gauss.size(); ++f) {
      Vector3d v = M * s.gauss[f];
      for (int k = 0; k < 3; ++k) v[k] = std::abs(v[k]) < kTinyComponent ? 0.0 : v[k];
      buf.g[f] = v, buf.g_nonzero[f] = nonzero_mask(v);
    }
    const MapLayout& m = *out.m;
    buf.c.resize(size_t(s.arcs)), buf.c_zero.resize(size_t(s.arcs));
    for (int e = 0; e < s.arcs; ++e) {
      const Vector3d &l = buf.g[m.arc[e].L], &r = buf.g[m.arc[e].R];
      buf.c[e] = l.cross(r), buf.c_zero[e] = pole_zero_mask(buf.g_nonzero[m.arc[e].L], buf.g_nonzero[m.arc[e].R]);
    }
    out.g = buf.g.data(), out.g_nonzero = buf.g_nonzero.data(), out.c = buf.c.data(), out.c_zero = buf.c_zero.data();
    out.rounded = false;  // (the turned vectors are the normals the predicates read)
  }
  if (!out.world.turned && out.world.t == Vector3d::Zero()) {
    out.px = s.px.data(), out.py = s.py.data(), out.pz = s.pz.data();
  } else {
    const size_t n = s.px.size();
    for (auto& p : buf.p) p.resize(n);
    out.world.place(s.px.data(), s.py.data(), s.pz.data(), n, {buf.p[0].data(), buf.p[1].data(), buf.p[2].data()});
    out.px = buf.p[0].data(), out.py = buf.p[1].data(), out.pz = buf.p[2].data();
  }
}

// Places each ray of `other` (counter-clockwise about n) among the sectors of `ref` (counter-
// clockwise, a face's: at least three, each turn less than pi): sector[j] = 2k + 1 when ray j
// points as ref's ray k does, 2k + 2 when it lies strictly between rays k and k + 1. The other
// rays run counter-clockwise too, so each one's search starts at the sector of the one before
// (both lists are read about once). False if a ray fits no sector (a map bent by rounding).
bool Overlay::place_rays(const Placed& N, int nf, const Placed& R, const std::vector<Ray>& ref, const Placed& O,
                         const std::vector<Ray>& other, std::vector<int>& sector) {
  const Vector3d& n = N.g[nf];
  const int nr = int(ref.size()), no = int(other.size());
  sector.resize(size_t(no));
  // The same rays (copies, aligned shapes, parallel prisms: the same neighbouring normals, which
  // canonical normals make the same vectors): one offset, found by comparing vectors.
  if (nr == no) {
    int k0 = 0;
    while (k0 < nr && !same_normal(R, ref[k0].to, O, other[0].to)) ++k0;
    bool same = k0 < nr;
    for (int j = 1; same && j < no; ++j) same = same_normal(R, ref[(k0 + j) % nr].to, O, other[j].to);
    if (same) {
      for (int j = 0; j < no; ++j) sector[j] = 2 * ((k0 + j) % nr) + 1;
      return true;
    }
  }
  // The turn from ref's ray k to a direction o, sign det(n, r_k, o) = o . (n x r_k): n x r_k
  // and its permanent (orient's filter) once per ray.
  turns.resize(size_t(nr));
  for (int k = 0; k < nr; ++k) {
    const Vector3d& r = R.gauss(ref[k].to);
    turns[k] = {n.cross(r), Vector3d(std::abs(n.y() * r.z()) + std::abs(n.z() * r.y()),
                                     std::abs(n.z() * r.x()) + std::abs(n.x() * r.z()),
                                     std::abs(n.x() * r.y()) + std::abs(n.y() * r.x()))};
  }
  // (Rounded normals: the filter also covers their own rounding, as orient_rounded_filter's.)
  const double slack = N.rounded || R.rounded || O.rounded ? 20 * kRoundedNormal : 0.0;
  const auto turn = [&](int k, int oj) {
    const Vector3d& o = O.g[oj];
    const double det = o.dot(turns[k].c), perm = o.cwiseAbs().dot(turns[k].bound);
    if (std::abs(det) > 1e-15 * perm + slack) return det > 0 ? 1 : -1;
    if (perm == 0) return 0;
    return slack > 0 ? orient_normals(O, oj, N, nf, R, ref[k].to) : orient_exact(o, n, R.g[ref[k].to]);
  };
  for (int j = 0, k = 0; j < no; ++j) {
    const int oj = other[j].to;
    for (int tried = 0;; k = (k + 1) % nr) {
      if (same_normal(R, ref[k].to, O, oj)) {  // the same normal (copies, aligned shapes): the same ray
        sector[j] = 2 * k + 1;
        break;
      }
      const int s0 = turn(k, oj);
      if (s0 >= 0 && turn((k + 1) % nr, oj) < 0) {
        sector[j] = 2 * k + (s0 == 0 ? 1 : 2);
        break;
      }
      if (++tried == nr) return false;
    }
  }
  return true;
}

bool Overlay::walk_a_arcs(const Placed& A, const Placed& B) {
  const MapLayout& ma = *A.m;
  const int F = A.s->faces;
  loc_b.assign(size_t(F), {Loc::Cell, -1}), queue.resize(size_t(F)), walked.assign(size_t(A.s->arcs), 0);
  face_sector.resize(ma.loop_cell.size());
  loc_a.assign(size_t(B.s->faces), {Loc::Cell, -1}), crossings.clear();
  if (!climb(B, A, 0, best_cell(B, A, 0), loc_b[0])) return false;
  queue[0] = 0;
  int tail = 1;
  // Breadth first over A's faces: each arc is walked once, from the face first reached, and
  // locates the other face's normal if that is not located yet.
  for (int q = 0; q < tail; ++q) {
    const int f = queue[q];
    const Loc here = loc_b[f];
    // From a face normal of B: A's rays there placed among B's once (not every walk reading
    // all of B's rays: two prisms' caps would cost the product of their sides).
    if (here.kind == Loc::Face) {
      rays_of(A, {Loc::Face, f}, rays[1]), rays_of(B, here, rays[0]);
      if (!place_rays(B, here.id, B, rays[0], A, rays[1], ray_sector)) return false;
      std::copy(ray_sector.begin(), ray_sector.end(), face_sector.begin() + ma.loop_start[f]);
    }
    for (int k = ma.loop_start[f]; k < ma.loop_start[f + 1]; ++k) {
      const int e = ma.loop_arc[k], g = ma.loop_face[k];
      if (walked[e]) continue;
      walked[e] = 1;
      Loc& to = loc_b[g];
      const bool known = to.id >= 0;
      if (known && to.kind == Loc::Cell && here.kind == Loc::Cell && to.id == here.id) continue;  // one cell
      WalkStart ahead;
      if (here.kind == Loc::Face) ahead = start_at(*B.m, here.id, face_sector[size_t(k)]);
      if (!walk(A, B, e, f, here, here.kind == Loc::Face ? &ahead : nullptr, to, known, crossings, loc_a)) return false;
      if (!known) queue[tail++] = g;
    }
  }
  return tail == F;
}

bool Overlay::locate_b_normals(const Placed& A, const Placed& B) {
  const MapLayout &ma = *A.m, &mb = *B.m;
  const int F = B.s->faces, E = B.s->arcs;
  // B's normals on A's normals; the arcs of B a normal of A lies inside (a walk along them may
  // change cell without a crossing); per arc of B, its crossings.
  b_arc_crossings.assign(size_t(E), 0), b_arc_last.resize(size_t(E));
  for (int f = 0; f < A.s->faces; ++f) {
    if (loc_b[f].kind == Loc::Face) loc_a[loc_b[f].id] = {Loc::Face, f};
    if (loc_b[f].kind == Loc::Arc) b_arc_crossings[loc_b[f].id] = 2;  // (climb across it)
  }
  for (int x = 0; x < int(crossings.size()); ++x) ++b_arc_crossings[crossings[x].eb], b_arc_last[crossings[x].eb] = x;
  queue.resize(size_t(F)), queued.assign(size_t(F), 0);
  int tail = 0;
  for (int g = 0; g < F && tail == 0; ++g)
    if (loc_a[g].id >= 0) queue[tail++] = g;
  if (tail == 0) {
    if (!climb(A, B, 0, best_cell(A, B, 0), loc_a[0])) return false;
    queue[tail++] = 0;
  }
  queued[queue[0]] = 1;
  // Breadth first over B's faces from a located one: across an arc of B that no arc of A
  // crosses the cell stays; across one crossed once it is the cell on the crossing's far side.
  for (int q = 0; q < tail; ++q) {
    const int g = queue[q];
    const Loc here = loc_a[g];
    for (int k = mb.loop_start[g]; k < mb.loop_start[g + 1]; ++k) {
      const int h = mb.loop_face[k], e = mb.loop_arc[k];
      if (queued[h]) continue;
      queued[h] = 1;
      if (loc_a[h].id >= 0) {
        queue[tail++] = h;
        continue;
      }
      const int n = b_arc_crossings[e];
      int cell = -1;
      if (here.kind == Loc::Cell && n == 0) cell = here.id;
      if (here.kind == Loc::Cell && n == 1) {
        const MapLayout::Arc& a = ma.arc[crossings[b_arc_last[e]].ea];
        cell = a.u == here.id ? a.v : a.v == here.id ? a.u : -1;
      }
      if (cell >= 0) {
        loc_a[h] = {Loc::Cell, cell};
      } else if (!climb(A, B, h, some_cell(A, here), loc_a[h])) {
        return false;
      }
      queue[tail++] = h;
    }
  }
  return tail == F;
}

bool Overlay::locate(Placed& A, Placed& B, bool small) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  A.is_a = true, B.is_a = false;
  if (A.rounded || B.rounded) {  // (the memos of rounded ties: per face of A and way; exact normals)
    // Both are exact answers about the prepared shapes in their body frames, whatever the common
    // pose, so they are kept while the pair is the same: a resting or coherent scene sums one
    // pair under one relative rotation call after call, and pays for each tie once. (B turned
    // against A: its ties depend on the rotation, and the memo is cleared.)
    const std::uint64_t pair[3] = {sa.id, B.own_frame ? sb.id : 0, B.negate};
    if (!std::equal(pair, pair + 3, tie_pair) || pair[0] == 0 || pair[1] == 0) {
      collinear.assign(2 * size_t(sa.faces), -1);
      std::copy(pair, pair + 3, tie_pair);
    }
    A.collinear = collinear.data();
    Placed* x[2] = {&A, &B};
    for (int k = 0; k < 2; ++k) {
      const size_t faces = size_t(x[k]->s->faces);
      if (x[k]->s->id != exact_shape[k] || exact_shape[k] == 0) {
        if (exact_terms[k].size() < faces * 3 * kMaxGaussTerms) exact_terms[k].resize(faces * 3 * kMaxGaussTerms);
        exact_count[k].assign(3 * faces, -1);
        if (near[k].size() < faces) near[k].resize(faces);  // (no clearing: each entry names its shape)
        exact_shape[k] = x[k]->s->id;
      }
      x[k]->exact_terms = exact_terms[k].data(), x[k]->exact_count = exact_count[k].data();
      x[k]->near_memo = near[k].data();
    }
  }
  dedupe_all = sa.polytope_ref->flat || sb.polytope_ref->flat;
  map_normals = std::max(sa.pole_slack, sb.pole_slack) > 1e-10;
  merged = false;
  // The small tables decline a pair with a tie (a sign of 0). With B not turned against A that
  // is a fact about the two shapes, whatever their common pose and translations, so it is kept
  // (tie_free) and the walks taken at once: a resting scene's tied pair pays for the tables once.
  small = small && !dedupe_all && small_overlay_fits(sa, sb);
  const std::uint64_t pair[3] = {sa.id, sb.id, B.negate};
  const bool known = B.own_frame && pair[0] != 0 && pair[1] != 0 && std::equal(pair, pair + 3, tie_free_pair);
  by_tables = small && (!known || tie_free) && locate_small(A, B);
  if (small && B.own_frame && !known) std::copy(pair, pair + 3, tie_free_pair), tie_free = by_tables;
  return by_tables || (walk_a_arcs(A, B) && locate_b_normals(A, B));
}

bool Overlay::run(Placed& A, Placed& B, MinkowskiSum& out, SumParts parts) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  if (!locate(A, B, true)) return false;
  crossing_slack = map_normals ? 0.0 : sa.pole_slack + sb.pole_slack;  // (crossing_normal's rules)
  crossing_certain = 4 * (2 * (sa.pole_error + sb.pole_error) + crossing_slack) <= 1e-6;
  // The planes need no loops; a flat operand's degenerate facets are found as loops that
  // collapse, so it takes the whole path, and its loops are dropped after.
  if (parts == SumParts::Planes && !dedupe_all) return write_planes(A, B, out);
  // The facets, written straight into `out`: at most one per face normal and crossing; loops
  // grow as they are written (a merged facet is longer than either face).
  const size_t facets = size_t(sa.faces + sb.faces) + crossings.size();
  // (The scratch only grows: a result's vectors are written once, at the end, without zeroing.)
  if (normal.size() < facets) normal.resize(facets), loose.resize(facets), facet_start.resize(facets + 1);
  const size_t entries = sa.map[0].loop_cell.size() + sb.map[0].loop_cell.size() + 4 * crossings.size();
  if (codes.size() < entries) codes.resize(entries);
  nf = nl = facet_start[0] = 0;
  pairs.reset(int(sa.px.size()), int(sb.px.size()), entries);
  if (!face_facets(A, B)) return false;
  crossing_facets(A, B);
  if (!number_and_write(A, B, out)) return false;
  if (parts == SumParts::Planes) {
    out.vertices.clear(), out.loop_start.clear(), out.loop_vertex.clear();
    out.V = out.E = 0, out.euler_ok = false, out.parts = SumParts::Planes;
  }
  return true;
}

inline void Overlay::begin_facet(const Vector3d& n, bool loose_offset, int length) {
  // Room for this loop, whatever the facets before it took.
  if (codes.size() < size_t(nl + length)) codes.resize(2 * size_t(nl + length));
  normal[nf] = n;
  loose[nf] = loose_offset;
}

inline void Overlay::end_facet(bool dedupe) {
  int* loop = codes.data();
  const int first = facet_start[nf];
  int n = nl - first;
  // A flat operand's prism has zero-length arcs, and merged facets meet rays of both maps at
  // one angle: drop the repeated vertices they make, and the facets left with fewer than three
  // (no area).
  if (dedupe) {
    int m = 0;
    for (int k = 0; k < n; ++k)
      if (m == 0 || loop[first + m - 1] != loop[first + k]) loop[first + m++] = loop[first + k];
    while (m > 1 && loop[first] == loop[first + m - 1]) --m;
    n = m >= 3 ? m : 0;
    nl = first + n;
    if (n == 0) return;
    // From its smallest pair, as every loop.
    int least = first;
    for (int k = first + 1; k < nl; ++k) least = pairs.less(loop[k], loop[least]) ? k : least;
    std::rotate(loop + first, loop + least, loop + nl);
  }
  facet_start[++nf] = nl;
}

bool Overlay::face_facets(const Placed& A, const Placed& B) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  const MapLayout &ma = *A.m, &mb = *B.m;
  // A's faces: face f (+) the vertex of its cell of B, or the merged facet.
  for (int f = 0; f < sa.faces; ++f) {
    const Loc& l = loc_b[f];
    if (l.kind != Loc::Cell) {
      if (!merged_facet(A, {Loc::Face, f}, B, l, true)) return false;
      continue;
    }
    // From its smallest pair: the face's smallest vertex.
    const int j = sb.cell_vertex[l.id], first = ma.loop_start[f], n = ma.loop_start[f + 1] - first;
    const int* cell = &ma.loop_cell[first];
    begin_facet(A.unit(f), map_normals, n);
    for (int k = ma.loop_least[f], m = 0; m < n; ++m, k = k + 1 < n ? k + 1 : 0) add_pair(sa.cell_vertex[cell[k]], j);
    end_facet(dedupe_all);
  }
  // B's faces, but those on a face normal of A (written above).
  for (int g = 0; g < sb.faces; ++g) {
    const Loc& l = loc_a[g];
    if (l.kind == Loc::Face) {
      if (loc_b[l.id].kind != Loc::Face || loc_b[l.id].id != g) return false;  // A's side saw the same
      continue;
    }
    if (l.kind == Loc::Arc) {
      if (!merged_facet(A, l, B, {Loc::Face, g}, false)) return false;
      continue;
    }
    const int i = sa.cell_vertex[l.id], first = mb.loop_start[g], n = mb.loop_start[g + 1] - first;
    const int* cell = &mb.loop_cell[first];
    begin_facet(B.unit(g), map_normals, n);
    for (int k = mb.loop_least[g], m = 0; m < n; ++m, k = k + 1 < n ? k + 1 : 0) add_pair(i, sb.cell_vertex[cell[k]]);
    end_facet(dedupe_all);
  }
  return true;
}

namespace {

// Crossing x's loop: the cells around it, (v1, p) (v1, q) (v0, q) (v0, p) as pairs[2 k],
// pairs[2 k + 1], with p, q = w0, w1 when s1 < 0 and w1, w0 when s1 > 0; returns the k of the
// smallest pair.
int crossing_pairs(const Placed& A, const Placed& B, const Crossing& x, int (&pairs)[8]) {
  const MapLayout::Arc &a = A.m->arc[x.ea], &b = B.m->arc[x.eb];
  const int p = B.s->cell_vertex[x.up ? b.v : b.u], q = B.s->cell_vertex[x.up ? b.u : b.v];
  const int a0 = A.s->cell_vertex[a.u], a1 = A.s->cell_vertex[a.v];
  pairs[0] = a1, pairs[1] = p, pairs[2] = a1, pairs[3] = q, pairs[4] = a0, pairs[5] = q, pairs[6] = a0, pairs[7] = p;
  return a1 < a0 ? (p < q ? 0 : 1) : (q < p ? 2 : 3);
}

}  // namespace

// A positive multiple of the unit normal of crossing x's facet, and its squared length (the
// callers scale many at once: unit_normals); loose_offset set where it is not the edges' own
// (the offset must then be the largest over the facet). The parallelogram e_A (+) e_B has normal
// +-(d_A x d_B), the sign from `up` (its crossing point X = a G_L' + b G_R', a, b > 0, has
// G_L' . (c x d_B) = -|d_B|^2 (d_A . G_L'), so X = -s1 c / |c|). That holds while d_A and d_B
// lie along their arcs' exact poles, to far less than the angle between them; else their cross
// product's direction, even its sign, is noise:
//  - edges within 1e-4 rad of parallel (the cross product cancels);
//  - a pole rounded from normals that nearly coincide (a short arc): G_L x G_R in double is
//    off the exact pole, which the walk's predicates follow, by up to pole_error;
//  - edges that stray from their arcs' poles (faces planar only to a tolerance, see
//    ShapeData::pole_slack): there the poles stand for the edges (map_normals; in the overlay
//    frame, A's body frame: a normal from them is turned by A's pose).
// Where the first rule fails, the circles' crossing from the poles; where that fails too, or
// the normal found is not on both arcs, near_parallel_normal: a normal in both arcs.
// Where the shapes' largest pole errors (twice, for a turned map's rounding) are far below
// 1e-4, the 1e-4 rule alone decides and the sign is certain; else each crossing's own.
// (Inlined: called out of line, its vector result and spills cost 37 instructions a crossing.)
[[gnu::always_inline]] inline Vector3d Overlay::crossing_normal(const Placed& A, const Placed& B, const Crossing& x,
                                                                bool& loose_offset, double& length2) const {
  const double slack = crossing_slack;
  const bool certain = crossing_certain;
  const double poles = certain ? 0.0 : pole_error(A, x.ea) + pole_error(B, x.eb);
  Vector3d da = map_normals ? A.pole(x.ea) : A.edge(x.ea), db = map_normals ? B.pole(x.eb) : B.edge(x.eb);
  Vector3d c = da.cross(db);
  double c2 = c.squaredNorm();
  if (!(c2 >= 0x1p-900 && c2 <= 0x1p900)) [[unlikely]] {
    // Edges at 1e71 and 1e84: c2 and |da|^2 |db|^2 overflow (a zero normal once scaled by
    // 1 / sqrt(inf)). Scaled by powers of two (exact), the same test and direction.
    da *= scale_to_one(da.cwiseAbs().maxCoeff()), db *= scale_to_one(db.cwiseAbs().maxCoeff());
    c = da.cross(db), c2 = c.squaredNorm();
  }
  const double edges = std::max(1e-4, 4 * (poles + slack));
  if (c2 > edges * edges * da.squaredNorm() * db.squaredNorm()) {
    Vector3d n = x.up ? -c : c;
    if (map_normals) n = A.world.turn(n);
    if (certain || on_arcs(A, x.ea, B, x.eb, n)) return length2 = c2, n;
  }
  loose_offset = true, length2 = 1;
  const Vector3d pa = A.pole(x.ea), pb = B.pole(x.eb), cp = pa.cross(pb);
  const double cp2 = cp.squaredNorm(), circles = std::max(1e-4, 4 * poles);
  if (cp2 > circles * circles * pa.squaredNorm() * pb.squaredNorm()) {
    const Vector3d n = A.world.turn(cp * ((x.up ? -1 : 1) / std::sqrt(cp2)));
    if (certain || on_arcs(A, x.ea, B, x.eb, n)) return n;
  }
  return near_parallel_normal(A.unit(A.L(x.ea)), A.unit(A.R(x.ea)), B.unit(B.L(x.eb)), B.unit(B.R(x.eb)));
}

void Overlay::crossing_facets(const Placed& A, const Placed& B) {
  // One pass: each crossing's loop from its smallest pair, and its normal (scaled to unit length
  // all together after: unit_normals).
  length2.resize(crossings.size());
  for (size_t k = 0; k < crossings.size(); ++k) {
    Crossing& x = crossings[k];
    int p[8];
    const int first = crossing_pairs(A, B, x, p);
    const int code[4] = {pairs.code(p[0], p[1]), pairs.code(p[2], p[3]), pairs.code(p[4], p[5]), pairs.code(p[6], p[7])};
    if (codes.size() < size_t(nl + 4)) codes.resize(2 * size_t(nl + 4));
    int* loop = codes.data() + nl;
    for (int q = 0; q < 4; ++q) loop[q] = code[(first + q) & 3];
    nl += 4;
    x.facet = nf;
    end_facet(dedupe_all);
    length2[k] = 1;
    if (x.facet == nf) {  // dropped: a flat operand's zero-length edge (a degenerate parallelogram)
      x.facet = -1;
      continue;
    }
    bool loose_offset = map_normals;
    normal[x.facet] = crossing_normal(A, B, x, loose_offset, length2[k]);
    loose[x.facet] = loose_offset;
  }
  unit_normals(length2);
  for (size_t k = 0; k < crossings.size(); ++k)
    if (crossings[k].facet >= 0) normal[crossings[k].facet] *= length2[k];
}

void unit_normals(std::vector<double>& length2) {
  // One pass the compiler vectorises: the roots and divisions of many normals overlap, where
  // one at a time each facet's offset waited behind its own (a third of write_planes' time).
  for (double& x : length2) x = 1 / std::sqrt(x);
}

// The facet at a normal where A's feature fa and B's feature fb meet, one of them a face (the
// reference: its rays split the turn around the normal into sectors of less than pi): the
// other's rays are placed among them (each in the sector [r_k, r_k+1) that holds it, exactly;
// on r_k itself where both point the same way), and every sector between two consecutive rays
// of either map is an overlay cell, a vertex (i, j) of the facet, counter-clockwise.
bool Overlay::merged_facet(const Placed& A, const Loc& fa, const Placed& B, const Loc& fb, bool normal_of_a) {
  merged = true;
  // The reference is B's face where there is one (A's rays among it were placed by the walks
  // when both are faces), else A's.
  const bool a_ref = fb.kind != Loc::Face;
  const Placed &R = a_ref ? A : B, &O = a_ref ? B : A;
  std::vector<Ray>&ref = rays[0], &other = rays[1];
  rays_of(R, a_ref ? fa : fb, ref);
  rays_of(O, a_ref ? fb : fa, other);
  const int nr = int(ref.size()), no = int(other.size());
  if (fa.kind == Loc::Face && fb.kind == Loc::Face) {
    const int first = A.m->loop_start[fa.id];
    ray_sector.assign(face_sector.begin() + first, face_sector.begin() + first + no);
  } else if (!place_rays(normal_of_a ? A : B, normal_of_a ? fa.id : fb.id, R, ref, O, other, ray_sector)) {
    return false;
  }
  // The cells before the first ray of R: R's cell before it, O's after its last ray (in the
  // order of the sectors, which is O's own order turned to start after r_0).
  int first_o = 0;  // where O's (counter-clockwise) sectors fall back to a smaller one
  for (int j = 0; j < no; ++j)
    if (ray_sector[(j + no - 1) % no] > ray_sector[j]) first_o = j;
  int cell_r = ref[nr - 1].after, cell_o = other[(first_o + no - 1) % no].after;
  begin_facet(normal_of_a ? A.unit(fa.id) : B.unit(fb.id), true, nr + no);
  int j = first_o, taken = 0;
  const auto emit = [&] {
    const int ca = a_ref ? cell_r : cell_o, cb = a_ref ? cell_o : cell_r;
    add_pair(A.s->cell_vertex[ca], B.s->cell_vertex[cb]);
  };
  for (int k = 0; k < nr; ++k) {
    cell_r = ref[k].after;
    // O's rays along r_k, then inside the sector after it.
    while (taken < no && ray_sector[j] == 2 * k + 1) cell_o = other[j].after, j = (j + 1) % no, ++taken;
    emit();
    while (taken < no && ray_sector[j] == 2 * k + 2) {
      cell_o = other[j].after, j = (j + 1) % no, ++taken;
      emit();
    }
  }
  if (taken != no) return false;
  end_facet(true);
  return true;
}

bool Overlay::number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const int F = nf, S = nl, V = pairs.count();
  // A closed polytope: every edge in two loops (E = S / 2), and V - E + F = 2.
  if (S % 2 != 0 || F < 4 || V - S / 2 + F != 2) return false;
  // Reserved to their exact sizes: a new result allocates each array once, not by doubling.
  out.vertices.clear(), out.planes.clear(), out.vertices.reserve(size_t(V)), out.planes.reserve(size_t(F));
  out.loop_start.assign(facet_start.begin(), facet_start.begin() + F + 1);
  out.loop_vertex.assign(codes.begin(), codes.begin() + S);
  int* loop = out.loop_vertex.data();
  pairs.finish(loop, size_t(S), [&](int, int i, int j) {
    out.vertices.push_back(SumVertex{i, j, A.point(i) + B.point(j)});
  });
  // Offsets: the support function at the loop's first pair (the smallest, so that a plane's
  // pair does not depend on the path), h_A(n) + h_B(n) (the paper's support planes), or, for
  // merged facets and slivers, the largest over the loop (no vertex cut off).
  const SumVertex* vertex = out.vertices.data();
  const int* start = out.loop_start.data();
  for (int f = 0; f < F; ++f) {
    const Vector3d& n = normal[f];
    const SumVertex& first = vertex[loop[start[f]]];
    double offset = n.dot(first.point);
    if (loose[f])
      for (int k = start[f] + 1; k < start[f + 1]; ++k) offset = std::max(offset, n.dot(vertex[loop[k]].point));
    out.planes.push_back(SumPlane{n, offset, first.i, first.j});
  }
  out.V = V, out.E = S / 2, out.F = F;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Fast, out.parts = SumParts::Whole;
  // Where features merged under a rotation (whose rounding could have bent a cell of B's map),
  // the result is proven a closed manifold whose planes support A and B. (Unturned maps are
  // the prepared ones, whose cells prepare proved convex, exactly.)
  return !merged || B.frame.cwiseAbs() == Eigen::Matrix3d::Identity() ||
         (closed_manifold(out) && planes_support(A, B, out));
}

// SumParts::Planes: each facet's plane and support pair from the located normals and the
// crossings, without loops, in the whole path's order. A facet of a face or a crossing gets
// the whole path's pair (its loop's smallest) and offset. A merged facet gets the pair of the
// highest vertices of A's and B's features, and their offset (the whole path's loop maximum,
// within rounding). It is certified as the whole path is (planes_support where features merged
// under a rotation), but for Euler's relation: there are no loops to count.
bool Overlay::write_planes(const Placed& A, const Placed& B, MinkowskiSum& out) {
  out.vertices.clear(), out.loop_start.clear(), out.loop_vertex.clear();
  // (At most one plane per face normal and crossing, written in place: the result keeps its size.)
  out.planes.resize(size_t(A.s->faces + B.s->faces) + crossings.size());
  SumPlane* next = out.planes.data();
  // Offset over the vertex pairs (i, j) the facet's loop would hold: `loose` takes the largest.
  const auto height = [&](const Vector3d& n, int i, int j) {
    return n.x() * (A.px[i] + B.px[j]) + n.y() * (A.py[i] + B.py[j]) + n.z() * (A.pz[i] + B.pz[j]);
  };
  const auto plane = [&](const Vector3d& n, int i, int j) { *next++ = SumPlane{n, height(n, i, j), i, j}; };
  const auto raise = [&](int i, int j) {
    SumPlane& p = next[-1];
    p.offset = std::max(p.offset, height(p.normal, i, j));
  };
  // The vertices of X's face f, from its smallest, through k = 0 ... n - 1.
  const auto face_vertex = [](const Placed& X, int f, int k) {
    const MapLayout& m = *X.m;
    const int first = m.loop_start[f], n = m.loop_start[f + 1] - first, at = m.loop_least[f] + k;
    return X.s->cell_vertex[m.loop_cell[first + (at < n ? at : at - n)]];
  };
  const auto face_size = [](const Placed& X, int f) { return X.m->loop_start[f + 1] - X.m->loop_start[f]; };
  // The highest vertex of X's feature l (a face's or an arc's) along n.
  const auto highest = [&](const Placed& X, const Loc& l, const Vector3d& n) {
    int best = -1;
    double top = 0;
    const auto consider = [&](int v) {
      const double h = n.dot(X.point(v));
      if (best < 0 || h > top) best = v, top = h;
    };
    if (l.kind == Loc::Face) {
      for (int k = 0; k < face_size(X, l.id); ++k) consider(face_vertex(X, l.id, k));
    } else {
      consider(X.s->cell_vertex[X.m->arc[l.id].u]), consider(X.s->cell_vertex[X.m->arc[l.id].v]);
    }
    return best;
  };
  for (int f = 0; f < A.s->faces; ++f) {
    const Loc& l = loc_b[f];
    const Vector3d n = A.unit(f);
    if (l.kind != Loc::Cell) {
      plane(n, highest(A, {Loc::Face, f}, n), highest(B, l, n));
      merged = true;
      continue;
    }
    const int j = B.s->cell_vertex[l.id];
    plane(n, face_vertex(A, f, 0), j);
    if (map_normals)
      for (int k = 1; k < face_size(A, f); ++k) raise(face_vertex(A, f, k), j);
  }
  for (int g = 0; g < B.s->faces; ++g) {
    const Loc& l = loc_a[g];
    const Vector3d n = B.unit(g);
    if (l.kind == Loc::Face) {
      if (loc_b[l.id].kind != Loc::Face || loc_b[l.id].id != g) return false;  // A's side saw the same
      continue;
    }
    if (l.kind == Loc::Arc) {
      plane(n, highest(A, l, n), highest(B, {Loc::Face, g}, n));
      merged = true;
      continue;
    }
    const int i = A.s->cell_vertex[l.id];
    plane(n, i, face_vertex(B, g, 0));
    if (map_normals)
      for (int k = 1; k < face_size(B, g); ++k) raise(i, face_vertex(B, g, k));
  }
  // The crossings' planes: their normals first (scaled to unit length together), then offsets.
  SumPlane* const crossing_planes = next;
  length2.resize(crossings.size()), loose_crossing.resize(crossings.size());
  for (size_t k = 0; k < crossings.size(); ++k) {
    const Crossing& x = crossings[k];
    int pairs[8];
    const int first = crossing_pairs(A, B, x, pairs);
    bool loose_offset = map_normals;
    *next++ = SumPlane{crossing_normal(A, B, x, loose_offset, length2[k]), 0, pairs[2 * first], pairs[2 * first + 1]};
    loose_crossing[k] = loose_offset;
  }
  unit_normals(length2);
  for (size_t k = 0; k < crossings.size(); ++k) {
    SumPlane& p = crossing_planes[k];
    p.normal *= length2[k];
    p.offset = height(p.normal, p.i, p.j);
    if (!loose_crossing[k]) continue;
    int pairs[8];
    crossing_pairs(A, B, crossings[k], pairs);
    for (int q = 0; q < 4; ++q) p.offset = std::max(p.offset, height(p.normal, pairs[2 * q], pairs[2 * q + 1]));
  }
  out.planes.resize(size_t(next - out.planes.data()));
  out.F = int(out.planes.size()), out.V = out.E = 0;
  out.euler_ok = false, out.corrected = false;
  out.method = Method::Fast, out.parts = SumParts::Planes;
  return !merged || B.frame.cwiseAbs() == Eigen::Matrix3d::Identity() || planes_support(A, B, out);
}

bool planes_support(const Placed& A, const Placed& B, const MinkowskiSum& m) {
  double size = 0;
  for (const Placed* x : {&A, &B})
    for (size_t k = 0; k < x->s->px.size(); ++k) size = std::max(size, x->point(int(k)).cwiseAbs().maxCoeff());
  const double tol = 1e-12 * size;
  // No neighbour of vertex v (through the arcs of its cell) is higher along n: local is global.
  const auto extreme = [tol](const Placed& x, int v, const Vector3d& n) {
    const ShapeData& s = *x.s;
    const MapLayout& m = *x.m;
    const int cell = s.vertex_cell[v];
    const double top = n.dot(x.point(v));
    for (int k = m.cell_start[cell]; k < m.cell_start[cell + 1]; ++k)
      if (n.dot(x.point(s.cell_vertex[m.cell_slot[k].next])) > top + tol) return false;
    return true;
  };
  for (int f = 0; f < m.F; ++f) {
    const SumPlane& p = m.planes[f];
    if (m.parts == SumParts::Planes) {
      if (!extreme(A, p.i, p.normal) || !extreme(B, p.j, p.normal)) return false;
      continue;
    }
    for (int v : m.facet(f))
      if (!extreme(A, m.vertices[v].i, p.normal) || !extreme(B, m.vertices[v].j, p.normal)) return false;
  }
  return true;
}

}  // namespace minksum::detail
