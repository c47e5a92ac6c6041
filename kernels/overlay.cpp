// A (+) B of two placed shapes by overlaying their Gauss maps, output-sensitively, for operands
// of any size (Barki, Denis & Dupont 2009; Fogel & Halperin 2007; arc crossings after
// Gregorius, GDC 2013).
//
// The facets of A (+) B are the vertices of the overlay of the two Gauss maps:
//  - each face normal N of A, with facet F_A(N) (+) F_B(N): the face plus the support feature
//    of B along N (a vertex; an edge or a face where N lies on B's arcs: merged facets);
//  - likewise each face normal of B that is not also one of A;
//  - each proper crossing of an arc e_A with an arc e_B: the parallelogram e_A (+) e_B.
// Arc e lies on the great circle normal to its direction d (N_L x N_R is a positive multiple of
// d), so which side of it a normal N lies on is the sign of d . N, kept when it clears a margin
// of 1e-11 of the largest coordinate (about 10^4 times the rounding); inside the margin the
// exact predicate decides on the normals themselves (orient, predicates.hpp).
//
// The algorithm walks (O(|E_A| + |E_B| + output) after the first support, which is a linear
// scan):
//  1. The cell of B holding A's first face normal: the best vertex, then a climb.
//  2. Every arc of A, from the face whose normal is located, is walked through B's map: B's
//     support moves one cell at a time, never back (the support of B's projection onto the
//     arc's plane turns by less than pi), and each move crosses one arc of B, a parallelogram
//     facet when the crossing is proper. The walk ends in the cell holding the arc's other end,
//     which locates that face's normal: a breadth-first order over A's faces locates them all.
//  3. Every face normal of B is located in A's map by climbing from a neighbour's cell.
//  4. The facets are written, the vertices (pairs (i, j)) numbered in (i, j) order by a
//     counting sort, and Euler's formula checked.
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

// The side of arc e's great circle (pole N_L x N_R, the edge's direction) on which the normal
// n lies, when the normal lies on the circle exactly: +-2 by the infinitesimal rotation of B
// about kAxis (n_moves: n is B's, else the arc is), 0 if even that leaves it on the circle.
[[gnu::noinline]] int perturbed_side(const Vector3d& n, const Vector3d& nl, const Vector3d& nr, bool n_moves) {
  // First order: (k x n) . c when n turns, n . (k x c) = -det(k, n, c) when the arc does.
  if (const int first = det_k_cross(n, nl, nr)) return 2 * (n_moves ? first : -first);
  // Second order (k x (k x n)) . c = n . (k x (k x c)) = (k . n)(k . c), given n . c = 0.
  return 2 * exact_sign_of_dot(kAxis, n) * orient(kAxis, nl, nr);
}

}  // namespace

int Placed::side(int e, const Placed& other, int f, double tol) const {
  const double v = dx[e] * other.nx[f] + dy[e] * other.ny[f] + dz[e] * other.nz[f];
  if (v > tol) return 1;
  if (v < -tol) return -1;
  const Vector3d n = other.normal(f), nl = normal(L(e)), nr = normal(R(e));
  if (const int s = orient(n, nl, nr)) return s;
  return perturbed_side(n, nl, nr, other.moves);
}

// The exact place of a normal in a map: inside a cell, inside an arc, or on a face normal.
struct Feature {
  enum Kind { Cell, Arc, Face } kind;
  int id;
};

void place(const ShapeData& s, const Eigen::Isometry3d& pose, bool negate, PlacedBuffers& buf, Placed& out) {
  out.s = &s, out.negate = negate;
  const Eigen::Matrix3d M = (negate ? -1.0 : 1.0) * pose.linear();
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
    out.dx = s.dx.data(), out.dy = s.dy.data(), out.dz = s.dz.data();
  } else {
    transform(s.nx, s.ny, s.nz, buf.n, Vector3d::Zero());
    transform(s.dx, s.dy, s.dz, buf.d, Vector3d::Zero());
    out.nx = buf.n[0].data(), out.ny = buf.n[1].data(), out.nz = buf.n[2].data();
    out.dx = buf.d[0].data(), out.dy = buf.d[1].data(), out.dz = buf.d[2].data();
  }
  if (M == Eigen::Matrix3d::Identity() && t == Vector3d::Zero()) {
    out.px = s.px.data(), out.py = s.py.data(), out.pz = s.pz.data();
  } else {
    transform(s.px, s.py, s.pz, buf.p, t);
    out.px = buf.p[0].data(), out.py = buf.p[1].data(), out.pz = buf.p[2].data();
  }
}

namespace {

// The feature of map X holding the normal f of Y, given a cell whose closure holds it: the
// arcs of the cell whose great circles hold it exactly (none: the cell; one: that arc; two:
// their common face). False for anything else.
bool exact_feature(const Placed& X, int cell, const Placed& Y, int f, Feature& out) {
  const ShapeData& s = *X.s;
  const Vector3d n = Y.normal(f);
  int zeros[2], nz = 0;
  for (int i = s.cell_start[cell]; i < s.cell_start[cell + 1]; ++i) {
    const int e = s.cell_arc[i];
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

// The cell of map X whose (perturbed) region holds the normal f of Y, by climbing from `cell`
// across the arcs it lies beyond (each step raises X's support along the normal); -1 on
// failure. `clean`: no side of the final cell was decided by the perturbation.
int climb(const Placed& X, const Placed& Y, int f, int cell, double tol, bool& clean) {
  const ShapeData& s = *X.s;
  for (int steps = 0; steps <= s.cells; ++steps) {
    int next = -1;
    clean = true;
    for (int i = s.cell_start[cell]; i < s.cell_start[cell + 1] && next < 0; ++i) {
      const int e = s.cell_arc[i];
      const int sg = X.side(e, Y, f, tol);
      if (sg == 0) return -1;
      clean &= sg == 1 || sg == -1;
      const ShapeData::Arc& a = s.arc[e];
      if ((sg > 0) == (a.u == cell)) next = a.u == cell ? a.v : a.u;  // the normal is beyond e
    }
    if (next < 0) return cell;
    cell = next;
  }
  return -1;
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

// Walks arc ea of A from its face `from_left ? L : R`, whose normal B's cell `cell` holds, to the
// cell holding its other end (returned; -1 on failure), appending the proper crossings. From a
// cell the next move is across the one arc e_B (not the one it came in by) that crosses e_A:
// e_B's circle separates N_L and N_R (s3 != s4), e_A's circle separates e_B's ends (s1 != s2),
// and not at the antipode (s1 == s4). None: the cell holds the other end. `clean`: no side of
// the end normal against the final cell's arcs was decided by the perturbation.
int walk(const Placed& A, const Placed& B, int ea, bool from_left, int cell, double tol,
         std::vector<Crossing>& out, bool& clean) {
  const ShapeData& sb = *B.s;
  const int fl = A.L(ea), fr = A.R(ea);
  int entry = -1;
  bool entry_clean = true;
  for (int steps = 0; steps <= sb.cells; ++steps) {
    int exit = -1, s[4] = {};
    clean = entry_clean;
    for (int i = sb.cell_start[cell]; i < sb.cell_start[cell + 1]; ++i) {
      const int e = sb.cell_arc[i];
      if (e == entry) continue;
      const int s3 = B.side(e, A, fl, tol), s4 = B.side(e, A, fr, tol);
      if (!s3 || !s4) return -1;
      const int end = from_left ? s4 : s3;
      clean &= end == 1 || end == -1;
      if ((s3 > 0) == (s4 > 0)) continue;
      const int s1 = A.side(ea, B, B.L(e), tol), s2 = A.side(ea, B, B.R(e), tol);
      if (!s1 || !s2) return -1;
      if ((s1 > 0) == (s2 > 0) || (s1 > 0) != (s4 > 0)) continue;
      exit = e, s[0] = s1, s[1] = s2, s[2] = s3, s[3] = s4;
      break;
    }
    if (exit < 0) return cell;
    // Proper without the perturbation: a parallelogram facet (else arcs touch or overlap, and
    // the facets there are the merged ones at face normals).
    if ((s[0] * s[0]) + (s[1] * s[1]) + (s[2] * s[2]) + (s[3] * s[3]) == 4) out.push_back({ea, exit, s[0] > 0});
    const int end = from_left ? s[3] : s[2];
    entry = exit, entry_clean = end == 1 || end == -1;
    cell = sb.arc[exit].u == cell ? sb.arc[exit].v : sb.arc[exit].u;
  }
  return -1;
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

void OverlayScratch::sector_loop(const Placed& A, const Feature& fa, const Placed& B, const Feature& fb, const Vector3d& n) {
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
  begin_facet(n, true);
  for (size_t k = 0; k < keyed.size(); ++k) {
    const Dir& d = keyed[k].second;
    (d.from_a ? ca : cb) = d.after;
    if (k + 1 < keyed.size() && same(keyed[k], keyed[k + 1])) continue;  // one merged boundary
    add_pair(A.s->cell_vertex[ca], B.s->cell_vertex[cb]);
  }
  end_facet();
}

void OverlayScratch::begin_facet(const Vector3d& n, bool loose) {
  normal.push_back(n), loose_offset.push_back(loose);
}

void OverlayScratch::end_facet() {
  // A flat operand's prism has zero-length arcs: drop the repeated pairs they make, and the
  // facets left with fewer than three (no area).
  int first = start.back(), n = int(pi.size()) - first;
  if (dedupe) {
    int m = 0;
    for (int k = 0; k < n; ++k) {
      const int i = pi[first + k], j = pj[first + k];
      if (m > 0 && pi[first + m - 1] == i && pj[first + m - 1] == j) continue;
      pi[first + m] = i, pj[first + m] = j, ++m;
    }
    while (m > 1 && pi[first] == pi[first + m - 1] && pj[first] == pj[first + m - 1]) --m;
    n = m;
  }
  if (n < 3) {
    normal.pop_back(), loose_offset.pop_back();
    n = 0;
  }
  pi.resize(size_t(first + n)), pj.resize(size_t(first + n));
  if (n) start.push_back(first + n);
}

bool OverlayScratch::run(const Placed& A, const Placed& B, double tol, MinkowskiSum& out) {
  const ShapeData &sa = *A.s, &sb = *B.s;
  normal.clear(), loose_offset.clear(), pi.clear(), pj.clear(), crossings.clear();
  start.assign(1, 0);
  dedupe = sa.polytope_ref->flat || sb.polytope_ref->flat;
  perturbed = false;
  // 1-2. A's face normals in B's map, by walking A's arcs breadth first from the first face.
  loc_b.assign(size_t(sa.faces), -1), clean_b.assign(size_t(sa.faces), 0);
  walked.assign(size_t(sa.arcs), 0);
  queue.clear();
  bool clean = true;
  loc_b[0] = climb(B, A, 0, best_cell(B, A, 0), tol, clean);
  if (loc_b[0] < 0) return false;
  clean_b[0] = clean;
  queue.push_back(0);
  for (size_t q = 0; q < queue.size(); ++q) {
    const int f = queue[q];
    for (int k = sa.loop_start[f]; k < sa.loop_start[f + 1]; ++k) {
      const int e = sa.loop_arc[k];
      if (walked[e]) continue;
      walked[e] = 1;
      const bool from_left = A.L(e) == f;
      const int g = from_left ? A.R(e) : A.L(e);
      const int end = walk(A, B, e, from_left, loc_b[f], tol, crossings, clean);
      if (end < 0) return false;
      if (loc_b[g] < 0) {
        loc_b[g] = end, clean_b[g] = clean;
        queue.push_back(g);
      } else if (loc_b[g] != end) {
        return false;  // two walks disagree: only an invalid shape does that
      }
    }
  }
  if (int(queue.size()) != sa.faces) return false;
  // 3. B's face normals in A's map, each climbing from a located neighbour's cell.
  loc_a.assign(size_t(sb.faces), -1), clean_a.assign(size_t(sb.faces), 0);
  queue.clear();
  loc_a[0] = climb(A, B, 0, best_cell(A, B, 0), tol, clean);
  if (loc_a[0] < 0) return false;
  clean_a[0] = clean;
  queue.push_back(0);
  for (size_t q = 0; q < queue.size(); ++q) {
    const int g = queue[q];
    for (int k = sb.loop_start[g]; k < sb.loop_start[g + 1]; ++k) {
      const int e = sb.loop_arc[k];
      const int h = B.L(e) == g ? B.R(e) : B.L(e);
      if (loc_a[h] >= 0) continue;
      loc_a[h] = climb(A, B, h, loc_a[g], tol, clean);
      if (loc_a[h] < 0) return false;
      clean_a[h] = clean;
      queue.push_back(h);
    }
  }
  if (int(queue.size()) != sb.faces) return false;
  // 4. The facets: A's faces, B's faces (not those with the normal of one of A's), crossings.
  coincide.assign(size_t(sb.faces), -1);
  for (int f = 0; f < sa.faces; ++f) {
    if (clean_b[f]) {  // face f (+) the vertex of B's cell
      const int j = sb.cell_vertex[loc_b[f]];
      begin_facet(A.normal(f), false);
      for (int k = sa.loop_start[f]; k < sa.loop_start[f + 1]; ++k) add_pair(sa.cell_vertex[sa.loop_cell[k]], j);
      end_facet();
      continue;
    }
    perturbed = true;
    Feature fb;
    if (!exact_feature(B, loc_b[f], A, f, fb) || fb.kind == Feature::Cell) return false;
    if (fb.kind == Feature::Face) coincide[fb.id] = f;
    sector_loop(A, {Feature::Face, f}, B, fb, A.normal(f));
  }
  for (int g = 0; g < sb.faces; ++g) {
    if (clean_a[g]) {
      if (coincide[g] >= 0) return false;
      const int i = sa.cell_vertex[loc_a[g]];
      begin_facet(B.normal(g), false);
      const int first = sb.loop_start[g], last = sb.loop_start[g + 1];
      for (int k = 0; k < last - first; ++k)  // -B's loops run the other way
        add_pair(i, sb.cell_vertex[sb.loop_cell[B.negate ? last - 1 - k : first + k]]);
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
    sector_loop(A, fa, B, {Feature::Face, g}, B.normal(g));
  }
  for (const Crossing& x : crossings) {
    const ShapeData::Arc &a = sa.arc[x.ea], &b = sb.arc[x.eb];
    // The parallelogram e_A (+) e_B, normal +-(d_A x d_B), the sign from s1 (its crossing point
    // X = a N_L' + b N_R', a, b > 0, has N_L' . (c x d_B) = -|d_B|^2 (d_A . N_L'), so
    // X = -s1 c / |c|). The cross product of edges within 1e-4 rad of parallel cancels (its
    // direction is good to 1e-16 / sin(angle) only): there the crossing point itself, from the
    // normals, which are perpendicular to the edges to rounding whatever the angle.
    const Vector3d da = A.dir(x.ea), db = B.dir(x.eb), c = da.cross(db);
    const double c2 = c.squaredNorm();
    const bool parallel = !(c2 > 1e-8 * da.squaredNorm() * db.squaredNorm());
    Vector3d n;
    if (!parallel) {
      n = c * ((x.up ? -1 : 1) / std::sqrt(c2));
    } else {
      const Vector3d a1 = A.normal(A.L(x.ea)), a2 = A.normal(A.R(x.ea));
      const Vector3d gb = B.normal(B.L(x.eb)).cross(B.normal(B.R(x.eb)));
      const Vector3d p = std::abs(a2.dot(gb)) * a1 + std::abs(a1.dot(gb)) * a2;
      n = p.norm() > 0 ? p.normalized() : Vector3d((a1 + a2).normalized());
    }
    // The cells around the crossing: (v1, p) (v1, q) (v0, q) (v0, p), with p, q = w0, w1 when
    // s1 < 0 and w1, w0 when s1 > 0.
    const int p = sb.cell_vertex[x.up ? b.v : b.u], q = sb.cell_vertex[x.up ? b.u : b.v];
    const int a0 = sa.cell_vertex[a.u], a1 = sa.cell_vertex[a.v];
    begin_facet(n, parallel);
    add_pair(a1, p), add_pair(a1, q), add_pair(a0, q), add_pair(a0, p);
    end_facet();
  }
  return number_and_write(A, B, out);
}

bool OverlayScratch::number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out) {
  const int nva = int(A.s->px.size()), nvb = int(B.s->px.size());
  const int F = int(normal.size()), S = int(pi.size());
  // The distinct pairs in (i, j) order: the entries bucketed by i (a counting sort), then within
  // a bucket the new j's in order (a few per i); O(S + |V_A| + |V_B|).
  bucket.assign(size_t(nva) + 1, 0);
  for (int k = 0; k < S; ++k) ++bucket[size_t(pi[k]) + 1];
  for (int i = 0; i < nva; ++i) bucket[i + 1] += bucket[i];
  order.resize(size_t(S)), fill.assign(bucket.begin(), bucket.end() - 1);
  for (int k = 0; k < S; ++k) order[size_t(fill[pi[k]]++)] = k;
  stamp.assign(size_t(nvb), -1), number_of_j.resize(size_t(nvb)), number.resize(size_t(S));
  out.vertices.clear();
  for (int i = 0; i < nva; ++i) {
    const int lo = bucket[i], hi = bucket[i + 1];
    if (lo == hi) continue;
    js.clear();
    for (int k = lo; k < hi; ++k)
      if (const int j = pj[order[k]]; stamp[j] != i) stamp[j] = i, js.push_back(j);
    std::sort(js.begin(), js.end());
    for (int j : js) {
      number_of_j[j] = int(out.vertices.size());
      out.vertices.push_back(SumVertex{i, j, A.point(i) + B.point(j)});
    }
    for (int k = lo; k < hi; ++k) number[order[k]] = number_of_j[pj[order[k]]];
  }
  const int V = int(out.vertices.size());
  // A closed polytope: every edge in two loops (E = S / 2), and V - E + F = 2.
  if (S % 2 != 0 || F < 4 || V - S / 2 + F != 2) return false;
  // Loops from their smallest vertex (so that a plane's pair does not depend on the path);
  // offsets the support function at that pair, h_A(n) + h_B(n) (the paper's support planes),
  // or, for merged facets and slivers, the largest over the loop (no vertex cut off).
  out.planes.resize(size_t(F)), out.loop_start.resize(size_t(F) + 1), out.loop_vertex.resize(size_t(S));
  out.loop_start[0] = 0;
  for (int f = 0; f < F; ++f) {
    const int lo = start[f], n = start[f + 1] - lo;
    int m = 0;
    for (int k = 1; k < n; ++k) m = number[lo + k] < number[lo + m] ? k : m;
    int* loop = &out.loop_vertex[size_t(lo)];
    for (int k = 0; k < n; ++k) loop[k] = number[lo + (m + k < n ? m + k : m + k - n)];
    out.loop_start[f + 1] = lo + n;
    SumPlane& plane = out.planes[f];
    const SumVertex& first = out.vertices[loop[0]];
    plane.normal = normal[f], plane.offset = normal[f].dot(first.point), plane.i = first.i, plane.j = first.j;
    if (loose_offset[f])
      for (int k = 1; k < n; ++k) plane.offset = std::max(plane.offset, normal[f].dot(out.vertices[loop[k]].point));
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
