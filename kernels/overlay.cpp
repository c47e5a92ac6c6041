// A (+) B of two placed shapes by overlaying their Gauss maps, output-sensitively, for operands
// of any size (Barki, Denis & Dupont 2009; Fogel & Halperin 2007; arc crossings after
// Gregorius, GDC 2013).
//
// The facets of A (+) B are the vertices of the overlay of the two Gauss maps:
//  - each face normal N of A, with facet F_A(N) (+) F_B(N): the face plus the support feature
//    of B along N (a vertex; an edge or a face where N lies on B's arcs: merged facets);
//  - likewise each face normal of B that is not also one of A;
//  - each proper crossing of an arc e_A with an arc e_B: the parallelogram e_A (+) e_B.
// Arc e lies on the great circle of pole c = N_L x N_R (a positive multiple of its edge), so
// which side of it a normal N lies on is the sign of c . N = det(N, N_L, N_R). The float value,
// c computed from the same normals, is within 2e-15 of the exact one for unit normals, so its
// sign is kept when it clears kFilter (a static filter, Shewchuk 1997); inside, the exact
// predicate decides (orient, predicates.hpp). Every sign is thus the exact sign on the normals
// as stored, and the walks see one consistent map, however close to parallel two faces are.
//
// The algorithm walks (O(|E_A| + |E_B| + output) after the first support, which is a linear
// scan):
//  1. Every face normal of A is located in B's map (the cell of B's support vertex), breadth
//     first over A's faces, each climbing from a neighbour's cell (hill climbing on B's
//     vertices, a few steps); the first one from B's best vertex. Likewise B's in A's map.
//  2. Every arc of A is walked through B's map from the cell of N_L to the cell of N_R: B's
//     support moves one cell at a time, never back (the support of B's projection onto the
//     arc's plane turns by less than pi), and each move crosses one arc of B, a parallelogram
//     facet when the crossing is proper. Arcs are taken face by face in that breadth-first
//     order, so that consecutive walks stay in one region of B's map (and of the cache).
//  3. The facets are written, their vertices (pairs (i, j)) hashed once, numbered in (i, j)
//     order by a counting sort, and Euler's formula checked.
// A normal that lies exactly on a great circle (parallel faces, an edge parallel to a face,
// touching arcs) makes a sign 0. The walks then follow the overlay of A and of B turned by an
// infinitesimal rotation about a fixed generic axis k (simulation of simplicity: the first
// nonzero term of the sign's expansion in the rotation angle, evaluated exactly), which is
// generic, so every step is decided; only crossings that are proper without the rotation
// become facets, and the facets at face normals on B's (or A's) arcs and normals are the
// merged polygons of the exact overlay, read off the directions around the normal (the
// sector loops below). Such a result is also checked as a closed manifold whose every plane
// supports A and B; a failure of any step (which only an invalid shape or an axis k that
// happens to be special causes) leaves the hull corrector to answer.
#include <algorithm>
#include <cmath>
#include <gmpxx.h>

#include "overlay.hpp"
#include "predicates.hpp"
#include "sum_internal.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

// The perturbation's rotation axis: generic (no face normal or arc pole of a real shape is
// parallel to it), exactly representable.
const Vector3d kAxis(0.7165812272381351, 0.3040129830587513, 0.6278406398735125);

// Exact sign of det(k, p, q x r) = (k . q)(p . r) - (k . r)(p . q).
int det_k_cross(const Vector3d& p, const Vector3d& q, const Vector3d& r) {
  const auto m = [](double x) { return mpq_class(x); };
  const auto dot = [&m](const Vector3d& x, const Vector3d& y) {
    return mpq_class(m(x.x()) * m(y.x()) + m(x.y()) * m(y.y()) + m(x.z()) * m(y.z()));
  };
  return sgn(dot(kAxis, q) * dot(p, r) - dot(kAxis, r) * dot(p, q));
}

int exact_sign_of_dot(const Vector3d& x, const Vector3d& y) {
  return sgn(mpq_class(x.x()) * mpq_class(y.x()) + mpq_class(x.y()) * mpq_class(y.y()) +
             mpq_class(x.z()) * mpq_class(y.z()));
}

// The side of arc e's great circle (pole c = N_L x N_R) on which the normal n lies, when it lies
// on the circle exactly: +-2 by the infinitesimal rotation of B about kAxis (n_moves: n is B's,
// else the arc is), 0 if even that leaves it on the circle.
[[gnu::noinline]] int perturbed_side(const Vector3d& n, const Vector3d& nl, const Vector3d& nr, bool n_moves) {
  // First order: (k x n) . c when n turns, n . (k x c) = -det(k, n, c) when the arc does.
  if (const int first = det_k_cross(n, nl, nr)) return 2 * (n_moves ? first : -first);
  // Second order (k x (k x n)) . c = n . (k x (k x c)) = (k . n)(k . c), given n . c = 0.
  return 2 * exact_sign_of_dot(kAxis, n) * orient(kAxis, nl, nr);
}

// The float filter of every sign (see the top of the file).
constexpr double kFilter = 1e-14;

// The sign of v when it clears the filter, else 0.
inline int margin_sign(double v) { return v > kFilter ? 1 : v < -kFilter ? -1 : 0; }

}  // namespace

int Placed::exact_side(int e, const Placed& other, int f) const {
  const Vector3d n = other.normal(f), nl = normal(L(e)), nr = normal(R(e));
  if (const int s = orient(n, nl, nr)) return s;
  return perturbed_side(n, nl, nr, other.moves);
}

void place(const ShapeData& s, const Eigen::Isometry3d& pose, bool negate, PlacedBuffers& buf, Placed& out) {
  out.s = &s, out.negate = negate;
  const Eigen::Matrix3d M = (negate ? -1.0 : 1.0) * pose.linear();
  out.linear = M, out.turned = M != Eigen::Matrix3d::Identity();
  const Vector3d t = (negate ? -1.0 : 1.0) * pose.translation();
  // x' = M x (+ t), by component over the arrays (vectorised).
  const auto transform = [&M](const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& z,
                              std::vector<double> (&o)[3], const Vector3d& shift) {
    const size_t n = x.size();
    for (int r = 0; r < 3; ++r) {
      o[r].resize(n);
      const double m0 = M(r, 0), m1 = M(r, 1), m2 = M(r, 2), c = shift[r];
      double* out = o[r].data();
      for (size_t k = 0; k < n; ++k) out[k] = m0 * x[k] + m1 * y[k] + m2 * z[k] + c;
    }
  };
  if (M == Eigen::Matrix3d::Identity()) {
    out.nx = s.nx.data(), out.ny = s.ny.data(), out.nz = s.nz.data();
    out.sx = s.sx.data(), out.sy = s.sy.data(), out.sz = s.sz.data();
  } else {
    // The poles from the placed normals themselves (not rotated): the filter's bound holds
    // against the exact predicate on those normals whatever the pose's rounding.
    transform(s.nx, s.ny, s.nz, buf.n, Vector3d::Zero());
    for (auto& d : buf.d) d.resize(s.sx.size());
    out.nx = buf.n[0].data(), out.ny = buf.n[1].data(), out.nz = buf.n[2].data();
    out.sx = buf.d[0].data(), out.sy = buf.d[1].data(), out.sz = buf.d[2].data();
    fill_poles(s, negate, out.nx, out.ny, out.nz, buf.d[0].data(), buf.d[1].data(), buf.d[2].data());
  }
  if (M == Eigen::Matrix3d::Identity() && t == Vector3d::Zero()) {
    out.px = s.px.data(), out.py = s.py.data(), out.pz = s.pz.data();
  } else {
    transform(s.px, s.py, s.pz, buf.p, t);
    out.px = buf.p[0].data(), out.py = buf.p[1].data(), out.pz = buf.p[2].data();
  }
}

// The exact place of a normal in a map: inside a cell, inside an arc, or on a face normal.
struct Feature {
  enum Kind { Cell, Arc, Face } kind;
  int id;
};

namespace {

// The feature of map X holding the normal f of Y, given a cell whose closure holds it: the
// arcs of the cell whose great circles hold it exactly (none: the cell; one: that arc; two:
// their common face). False for anything else.
bool exact_feature(const Placed& X, int cell, const Placed& Y, int f, Feature& out) {
  const ShapeData& s = *X.s;
  const Vector3d n = Y.normal(f);
  int zeros[2], nz = 0;
  for (int k = s.cell_start[cell]; k < s.cell_start[cell + 1]; ++k) {
    const int e = s.cell_slot[k].arc >= 0 ? s.cell_slot[k].arc : ~s.cell_slot[k].arc;
    if (orient(n, X.normal(X.L(e)), X.normal(X.R(e))) != 0) continue;
    if (nz == 2) return false;
    zeros[nz++] = e;
  }
  if (nz == 0) {
    out = {Feature::Cell, cell};
  } else if (nz == 1) {
    out = {Feature::Arc, zeros[0]};
  } else {
    const int l0 = X.L(zeros[0]), r0 = X.R(zeros[0]), l1 = X.L(zeros[1]), r1 = X.R(zeros[1]);
    out = {Feature::Face, (l0 == l1 || l0 == r1) ? l0 : r0};
  }
  return true;
}

// The cell of X best along the normal f of Y, by a linear scan (the first support only).
int best_cell(const Placed& X, const Placed& Y, int f) {
  const ShapeData& s = *X.s;
  int best = 0;
  double top = -std::numeric_limits<double>::infinity();
  for (int c = 0; c < s.cells; ++c) {
    const int v = s.cell_vertex[c];
    const double h = Y.nx[f] * X.px[v] + Y.ny[f] * X.py[v] + Y.nz[f] * X.pz[v];
    if (h > top) top = h, best = c;
  }
  return best;
}

// The cell of map X whose (perturbed) region holds the normal f of Y, by climbing from `cell`
// across the arcs it lies beyond (each step raises X's support along the normal); -1 on
// failure. `clean`: no side of the final cell was decided by the perturbation.
int climb(const Placed& X, const Placed& Y, int f, int cell, bool& clean) {
  const ShapeData& s = *X.s;
  const double nx = Y.nx[f], ny = Y.ny[f], nz = Y.nz[f];
  const double *sx = X.sx, *sy = X.sy, *sz = X.sz;
  const int* start = s.cell_start.data();
  const ShapeData::Slot* slot = s.cell_slot.data();
  clean = true;
  for (int steps = 0; steps <= s.cells; ++steps) {
    int next = -1;
    for (int k = start[cell], end = start[cell + 1]; k < end; ++k) {
      const double v = sx[k] * nx + sy[k] * ny + sz[k] * nz;
      if (v < -kFilter) continue;
      int b = v > kFilter ? 1 : X.exact_beyond(k, Y, f);
      if (b == 0) return -1;
      if (b > 0) {
        next = slot[k].next;
        break;
      }
      if (b == -2) clean = false;  // on the arc's circle exactly
    }
    if (next < 0) return cell;
    cell = next;
    clean = true;
  }
  return -1;
}

// Walks arc ea of A from the normal of its face `from`, which B's cell `cell` holds, towards the
// normal of its other face `to`: to the cell `target` when that is known (>= 0), else until a
// cell holds it, certified (it lies beyond none of the cell's arcs; `clean`: none of those
// sides was decided by the perturbation). Returns the last cell (-1 on failure) and appends
// the proper crossings. From a cell the next move is across the one arc e_B that crosses e_A:
// N_to lies beyond it and N_from does not (e_B's circle separates N_L and N_R: s3 != s4; the
// arc it came in by has N_to behind it), e_A's circle separates e_B's ends (s1 != s2), and not
// at the antipode (s1 == s4).
int walk(const Placed& A, const Placed& B, int ea, int from, int cell, int target, std::vector<Crossing>& out,
         bool& clean) {
  const ShapeData& sb = *B.s;
  const bool from_left = A.L(ea) == from;
  const int to = from_left ? A.R(ea) : A.L(ea);
  const double tx = A.nx[to], ty = A.ny[to], tz = A.nz[to], fx = A.nx[from], fy = A.ny[from], fz = A.nz[from];
  const Vector3d da = A.pole(ea);
  const double *sx = B.sx, *sy = B.sy, *sz = B.sz, *nx = B.nx, *ny = B.ny, *nz = B.nz;
  const int* start = sb.cell_start.data();
  const ShapeData::Slot* slot = sb.cell_slot.data();
  for (int steps = 0; cell != target; ++steps) {
    if (steps > sb.cells) return -1;
    int k = start[cell], exit = -1, s1 = 0, s2 = 0, s3 = 0, s4 = 0;
    bool beyond_some = false;
    clean = true;
    for (const int end = start[cell + 1]; k < end; ++k) {
      const double vt = sx[k] * tx + sy[k] * ty + sz[k] * tz;
      if (vt < -kFilter) continue;
      const int to_beyond = vt > kFilter ? 1 : B.exact_beyond(k, A, to);
      if (to_beyond <= 0) {
        if (to_beyond == 0) return -1;
        clean &= to_beyond == -1;
        continue;
      }
      beyond_some = true;
      const double vf = sx[k] * fx + sy[k] * fy + sz[k] * fz;
      const int from_beyond = vf < -kFilter ? -1 : vf > kFilter ? 1 : B.exact_beyond(k, A, from);
      if (from_beyond >= 0) {
        if (from_beyond == 0) return -1;
        continue;
      }
      // s3, s4: the signs of d_B . N_L and d_B . N_R (read from u, the slot's direction is d_B).
      const int a = slot[k].arc, e = a >= 0 ? a : ~a, sign = a >= 0 ? 1 : -1;
      s3 = sign * (from_left ? from_beyond : to_beyond), s4 = sign * (from_left ? to_beyond : from_beyond);
      const int gl = B.L(e), gr = B.R(e);
      s1 = margin_sign(da.x() * nx[gl] + da.y() * ny[gl] + da.z() * nz[gl]);
      if (!s1 && !(s1 = A.exact_side(ea, B, gl))) return -1;
      if ((s1 > 0) != (s4 > 0)) continue;
      s2 = margin_sign(da.x() * nx[gr] + da.y() * ny[gr] + da.z() * nz[gr]);
      if (!s2 && !(s2 = A.exact_side(ea, B, gr))) return -1;
      if ((s1 > 0) == (s2 > 0)) continue;
      exit = e;
      break;
    }
    if (exit < 0) return target < 0 && !beyond_some ? cell : -1;
    // Proper without the perturbation: a parallelogram facet (else arcs touch or overlap, and
    // the facets there are the merged ones at face normals).
    if (s1 * s1 + s2 * s2 + s3 * s3 + s4 * s4 == 4) out.push_back({ea, exit, s1 > 0});
    cell = slot[k].next;
  }
  return cell;
}

// The normal of the parallelogram of two edges within 1e-4 rad of parallel, whose arcs
// (a1 -> a2, b1 -> b2, each shorter than pi) cross: the point of A's arc where B's circle
// crosses it, clamped into the part of A's arc that B's arc spans. When the edges are parallel
// to rounding the two circles coincide and the crossing point is noise, but any normal in both
// arcs supports both edges, so the clamp keeps the plane a support plane of A and of B.
Vector3d near_parallel_normal(const Vector3d& a1, const Vector3d& a2, const Vector3d& b1, const Vector3d& b2) {
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

// The directions leaving a facet normal along the arcs of feature f of X, each towards a normal
// m, with the cell counter-clockwise after it (seen from outside).
void directions(const Placed& X, const Feature& f, bool from_a, std::vector<OverlayScratch::Dir>& out) {
  using Dir = OverlayScratch::Dir;
  const ShapeData& s = *X.s;
  const auto add = [&](int e, bool towards_r) {
    // Walking towards R, cell v is on the left (counter-clockwise) side; towards L, cell u.
    out.push_back(towards_r ? Dir{X.normal(X.R(e)), s.arc[e].v, from_a} : Dir{X.normal(X.L(e)), s.arc[e].u, from_a});
  };
  if (f.kind == Feature::Face)
    for (int k = s.loop_start[f.id]; k < s.loop_start[f.id + 1]; ++k) add(s.loop_arc[k], X.L(s.loop_arc[k]) == f.id);
  if (f.kind == Feature::Arc) add(f.id, true), add(f.id, false);
}

}  // namespace

inline void OverlayScratch::begin_facet(MinkowskiSum& out, const Vector3d& n, bool loose_offset) {
  out.planes[nf].normal = n;
  loose[nf] = loose_offset;
}

inline void OverlayScratch::add_pair(int i, int j) {
  // Open addressing on the key (i, j) (Fibonacci hashing), grown at half load.
  const std::uint64_t key = std::uint64_t(i) << 32 | std::uint64_t(unsigned(j));
  unsigned h = unsigned((key * 0x9E3779B97F4A7C15ull) >> shift);
  for (;; h = (h + 1) & mask) {
    if (slot_key[h] == key) {
      loop[nl++] = slot_id[h];
      return;
    }
    if (slot_key[h] == kEmpty) break;
  }
  const int id = int(id_key.size());
  slot_key[h] = key, slot_id[h] = id, loop[nl++] = id;
  id_key.push_back(key);
  if (2 * id_key.size() > mask) grow();
}

void OverlayScratch::grow() {
  const unsigned size = 2 * (mask + 1);
  slot_key.assign(size, kEmpty), slot_id.resize(size), mask = size - 1, --shift;
  for (size_t id = 0; id < id_key.size(); ++id) {
    unsigned g = unsigned((id_key[id] * 0x9E3779B97F4A7C15ull) >> shift);
    while (slot_key[g] != kEmpty) g = (g + 1) & mask;
    slot_key[g] = id_key[id], slot_id[g] = int(id);
  }
}

inline void OverlayScratch::end_facet() {
  const int first = start[nf];
  int n = nl - first;
  // A flat operand's prism has zero-length arcs: drop the repeated vertices they make, and the
  // facets left with fewer than three (no area).
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
    for (int k = first + 1; k < nl; ++k) least = id_key[loop[k]] < id_key[loop[least]] ? k : least;
    std::rotate(loop.begin() + first, loop.begin() + least, loop.begin() + nl);
  }
  start[++nf] = nl;
}

bool OverlayScratch::run(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  crossings.clear();
  dedupe = sa.polytope_ref->flat || sb.polytope_ref->flat;
  map_normals = std::max(sa.pole_slack, sb.pole_slack) > 1e-10;
  perturbed = false;
  // 1. A's face normals in B's map, and the crossings: breadth first over A's faces from the
  //    first (located by B's best vertex and a climb), every arc of a located face is walked
  //    to its other face, whose normal the walk locates if it is not yet (so that consecutive
  //    walks stay in one region of B's map, and of the cache).
  loc_b.assign(size_t(sa.faces), -1), clean_b.resize(size_t(sa.faces)), queue.resize(size_t(sa.faces));
  walked.assign(size_t(sa.arcs), 0);
  bool clean = true;
  if ((loc_b[0] = climb(B, A, 0, best_cell(B, A, 0), clean)) < 0) return false;
  clean_b[0] = clean, queue[0] = 0;
  int tail = 1;
  for (int q = 0; q < tail; ++q) {
    const int f = queue[q];
    for (int k = sa.loop_start[f]; k < sa.loop_start[f + 1]; ++k) {
      const int e = sa.loop_arc[k], g = sa.loop_face[k];
      if (walked[e]) continue;
      walked[e] = 1;
      const int end = walk(A, B, e, f, loc_b[f], loc_b[g], crossings, clean);
      if (end < 0) return false;
      if (loc_b[g] < 0) loc_b[g] = end, clean_b[g] = clean, queue[tail++] = g;
    }
  }
  if (tail != sa.faces) return false;
  // 2. B's face normals in A's map, breadth first too, each climbing from the cell a crossing
  //    of one of its arcs puts it in (the side of e_A's circle it lies on: s1 or s2), else from
  //    a neighbour's.
  loc_a.assign(size_t(sb.faces), -1), clean_a.resize(size_t(sb.faces)), hint.assign(size_t(sb.faces), -1);
  queue.resize(size_t(sb.faces));
  for (const Crossing& x : crossings) {
    const ShapeData::Arc& a = sa.arc[x.ea];
    hint[B.L(x.eb)] = x.up ? a.v : a.u, hint[B.R(x.eb)] = x.up ? a.u : a.v;
  }
  if ((loc_a[0] = climb(A, B, 0, hint[0] >= 0 ? hint[0] : best_cell(A, B, 0), clean)) < 0) return false;
  clean_a[0] = clean, queue[0] = 0, tail = 1;
  for (int q = 0; q < tail; ++q) {
    const int g = queue[q];
    for (int k = sb.loop_start[g]; k < sb.loop_start[g + 1]; ++k) {
      const int h = sb.loop_face[k];
      if (loc_a[h] >= 0) continue;
      if ((loc_a[h] = climb(A, B, h, hint[h] >= 0 ? hint[h] : loc_a[g], clean)) < 0) return false;
      clean_a[h] = clean, queue[tail++] = h;
    }
  }
  if (tail != sb.faces) return false;
  // 3. The facets: at most one per face normal and crossing, each loop at most as long as the
  //    face's (a merged one as both features': sector_loop makes room), four per crossing.
  const size_t facets = size_t(sa.faces + sb.faces) + crossings.size();
  const size_t entries = sa.loop_cell.size() + sb.loop_cell.size() + 4 * crossings.size();
  out.planes.resize(facets), loose.resize(facets), start.resize(facets + 1), loop.resize(entries);
  nf = nl = start[0] = 0;
  id_key.clear();
  unsigned size = 64;  // twice the vertices at most (each is in three loops or more)
  for (shift = 58; 3 * size < 2 * entries; size *= 2) --shift;
  slot_key.assign(size, kEmpty), slot_id.resize(size), mask = size - 1;
  if (!face_facets(A, B, out)) return false;
  crossing_facets(A, B, out);
  return number_and_write(A, B, out);
}

bool OverlayScratch::face_facets(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  // A's faces: face f (+) the vertex of its cell of B, or the merged facet where f's normal lies
  // on B's arcs.
  coincide.assign(size_t(sb.faces), -1);
  for (int f = 0; f < sa.faces; ++f) {
    if (clean_b[f]) {  // from its smallest pair: the face's smallest vertex
      const int j = sb.cell_vertex[loc_b[f]], first = sa.loop_start[f], n = sa.loop_start[f + 1] - first;
      const int* cell = &sa.loop_cell[first];
      begin_facet(out, A.normal(f), map_normals);
      for (int k = sa.loop_least[f], m = 0; m < n; ++m, k = k + 1 < n ? k + 1 : 0) add_pair(sa.cell_vertex[cell[k]], j);
      end_facet();
      continue;
    }
    perturbed = true;
    Feature fb;
    if (!exact_feature(B, loc_b[f], A, f, fb) || fb.kind == Feature::Cell) return false;
    if (fb.kind == Feature::Face) coincide[fb.id] = f;
    sector_loop(A, {Feature::Face, f}, B, fb, A.normal(f), out);
  }
  // B's faces, but those with the normal of one of A's (done above).
  for (int g = 0; g < sb.faces; ++g) {
    if (clean_a[g]) {  // (-B's loops run the other way)
      if (coincide[g] >= 0) return false;
      const int i = sa.cell_vertex[loc_a[g]], first = sb.loop_start[g], n = sb.loop_start[g + 1] - first;
      const int* cell = &sb.loop_cell[first];
      const int step = B.negate ? n - 1 : 1;
      begin_facet(out, B.normal(g), map_normals);
      for (int k = sb.loop_least[g], m = 0; m < n; ++m, k = k + step < n ? k + step : k + step - n)
        add_pair(i, sb.cell_vertex[cell[k]]);
      end_facet();
      continue;
    }
    perturbed = true;
    Feature fa;
    if (!exact_feature(A, loc_a[g], B, g, fa) || fa.kind == Feature::Cell) return false;
    if (fa.kind == Feature::Face) {
      if (coincide[g] != fa.id) return false;  // A's side must have found the same pair
      continue;
    }
    sector_loop(A, fa, B, {Feature::Face, g}, B.normal(g), out);
  }
  return true;
}

void OverlayScratch::crossing_facets(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  for (const Crossing& x : crossings) {
    const ShapeData::Arc &a = sa.arc[x.ea], &b = sb.arc[x.eb];
    // The parallelogram e_A (+) e_B, normal +-(d_A x d_B), the sign from s1 (its crossing point
    // X = a N_L' + b N_R', a, b > 0, has N_L' . (c x d_B) = -|d_B|^2 (d_A . N_L'), so
    // X = -s1 c / |c|). The cross product of edges within 1e-4 rad of parallel cancels (its
    // direction is good to 1e-16 / sin(angle) only): there the crossing point itself, from the
    // normals, which are perpendicular to the edges to rounding whatever the angle.
    // Edges that stray from their arcs' poles (faces planar only to a tolerance, see
    // ShapeData::pole_slack) would tilt the plane out of the crossing's cells: there the poles.
    const Vector3d da = map_normals ? A.pole(x.ea) : A.edge(x.ea), db = map_normals ? B.pole(x.eb) : B.edge(x.eb);
    const Vector3d c = da.cross(db);
    const double c2 = c.squaredNorm();
    const bool parallel = !(c2 > 1e-8 * da.squaredNorm() * db.squaredNorm());
    Vector3d n;
    if (!parallel) {
      n = c * ((x.up ? -1 : 1) / std::sqrt(c2));
    } else {
      // Edges that cancel (or a prism's zero-length edge) on arcs whose circles do not: the
      // circles' crossing, from the poles; circles that coincide too: near_parallel_normal.
      const Vector3d pa = A.pole(x.ea), pb = B.pole(x.eb), cp = pa.cross(pb);
      const double cp2 = cp.squaredNorm();
      n = cp2 > 1e-8 * pa.squaredNorm() * pb.squaredNorm()
              ? Vector3d(cp * ((x.up ? -1 : 1) / std::sqrt(cp2)))
              : near_parallel_normal(A.normal(A.L(x.ea)), A.normal(A.R(x.ea)), B.normal(B.L(x.eb)), B.normal(B.R(x.eb)));
    }
    // The cells around the crossing: (v1, p) (v1, q) (v0, q) (v0, p), with p, q = w0, w1 when
    // s1 < 0 and w1, w0 when s1 > 0; from the smallest pair.
    const int p = sb.cell_vertex[x.up ? b.v : b.u], q = sb.cell_vertex[x.up ? b.u : b.v];
    const int a0 = sa.cell_vertex[a.u], a1 = sa.cell_vertex[a.v];
    const int pairs[8] = {a1, p, a1, q, a0, q, a0, p};
    const int first = a1 < a0 ? (p < q ? 0 : 1) : (q < p ? 2 : 3);
    begin_facet(out, n, parallel || map_normals);
    for (int k = 0; k < 4; ++k) add_pair(pairs[2 * ((first + k) & 3)], pairs[2 * ((first + k) & 3) + 1]);
    end_facet();
  }
}

void OverlayScratch::sector_loop(const Placed& A, const Feature& fa, const Placed& B, const Feature& fb,
                                 const Vector3d& n, MinkowskiSum& out) {
  dirs.clear();
  directions(A, fa, true, dirs);
  directions(B, fb, false, dirs);
  const Vector3d ref = dirs[0].m;
  const auto tangent = [&](const Vector3d& m) { return Vector3d(m - n.dot(m) * n); };
  // Angle classes about n from ref: 0 = ref's direction, 1 = (0, 180), 2 = 180, 3 = (180, 360).
  const auto angle_class = [&](const Vector3d& m) {
    const int s = orient(n, ref, m);
    if (s != 0) return s > 0 ? 1 : 3;
    return tangent(ref).dot(tangent(m)) > 0 ? 0 : 2;
  };
  keyed.clear();
  for (const auto& d : dirs) keyed.emplace_back(angle_class(d.m), d);
  const auto same = [&](const auto& x, const auto& y) {
    return x.first == y.first && (x.first % 2 == 0 || orient(n, x.second.m, y.second.m) == 0);
  };
  std::sort(keyed.begin(), keyed.end(), [&](const auto& x, const auto& y) {
    if (x.first != y.first) return x.first < y.first;
    return x.first % 2 == 1 && orient(n, x.second.m, y.second.m) > 0;
  });
  // The cell before the first direction is the one after the last direction of each map.
  int ca = fa.kind == Feature::Cell ? fa.id : -1, cb = fb.kind == Feature::Cell ? fb.id : -1;
  for (const auto& [cls, d] : keyed) (d.from_a ? ca : cb) = d.after;
  if (loop.size() < size_t(nl) + keyed.size()) loop.resize(2 * (size_t(nl) + keyed.size()));
  begin_facet(out, n, true);
  for (size_t k = 0; k < keyed.size(); ++k) {
    const Dir& d = keyed[k].second;
    (d.from_a ? ca : cb) = d.after;
    if (k + 1 < keyed.size() && same(keyed[k], keyed[k + 1])) continue;  // one merged boundary
    add_pair(A.s->cell_vertex[ca], B.s->cell_vertex[cb]);
  }
  // (Repeats: two maps' directions that coincide on one side; the loop is the merged polygon.)
  const bool was = dedupe;
  dedupe = true;
  end_facet();
  dedupe = was;
}

bool OverlayScratch::number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const int nva = int(A.s->px.size()), F = nf, S = nl, V = int(id_key.size());
  out.planes.resize(size_t(F));
  // A closed polytope: every edge in two loops (E = S / 2), and V - E + F = 2.
  if (S % 2 != 0 || F < 4 || V - S / 2 + F != 2) return false;
  // The vertices in (i, j) order: the ids counted by i, then sorted by j within one i by
  // insertion (a few per i); O(V + |V_A|).
  bucket.assign(size_t(nva) + 1, 0), order.resize(size_t(V)), final_id.resize(size_t(V));
  for (const std::uint64_t key : id_key) ++bucket[size_t(key >> 32) + 1];
  for (int i = 0; i < nva; ++i) bucket[i + 1] += bucket[i];
  fill.assign(bucket.begin(), bucket.end() - 1);
  for (int id = 0; id < V; ++id) {
    const int i = int(id_key[id] >> 32), lo = bucket[i];
    int at = fill[i]++;
    for (; at > lo && id_key[order[at - 1]] > id_key[id]; --at) order[at] = order[at - 1];
    order[at] = id;
  }
  out.vertices.resize(size_t(V));
  for (int v = 0; v < V; ++v) {
    const std::uint64_t key = id_key[order[v]];
    const int i = int(key >> 32), j = int(key & 0xffffffffu);
    final_id[order[v]] = v;
    out.vertices[v] = SumVertex{i, j, A.point(i) + B.point(j)};
  }
  // The loops, each from its smallest vertex (so that a plane's pair does not depend on the
  // path); offsets the support function at that pair, h_A(n) + h_B(n) (the paper's support
  // planes), or, for merged facets and slivers, the largest over the loop (no vertex cut off).
  out.loop_start.assign(start.begin(), start.begin() + F + 1), out.loop_vertex.resize(size_t(S));
  const int *id = loop.data(), *final_of = final_id.data();
  int* loop_vertex = out.loop_vertex.data();
  for (int k = 0; k < S; ++k) loop_vertex[k] = final_of[id[k]];
  const SumVertex* vertex = out.vertices.data();
  for (int f = 0; f < F; ++f) {
    SumPlane& plane = out.planes[f];
    const SumVertex& first = vertex[loop_vertex[start[f]]];
    plane.offset = plane.normal.dot(first.point), plane.i = first.i, plane.j = first.j;
    if (loose[f])
      for (int k = start[f] + 1; k < start[f + 1]; ++k)
        plane.offset = std::max(plane.offset, plane.normal.dot(vertex[loop_vertex[k]].point));
  }
  out.V = V, out.E = S / 2, out.F = F;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Fast;
  // Facets from the exact overlay's degenerate places: proven a closed manifold whose planes
  // support A and B before they count.
  return !perturbed || (closed_manifold(out) && planes_support(A, B, out));
}

}  // namespace minksum::detail
