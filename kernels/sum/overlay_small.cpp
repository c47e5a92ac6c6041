// Steps 1 and 2 of the overlay (overlay.cpp) for small operands (small_overlay_fits: at most 64
// arcs each, and few products per walk step), from tables of signs instead of walks (#29's
// small fused overlay). Every sign of the overlay is
// the side of a face normal of one operand against an arc of the other, c . G. The tables hold
// all of them, F_B E_A + F_A E_B products computed in bulk across SIMD lanes (side_masks, the
// active ISA), as bit masks:
//  - a proper crossing of arcs e_A and e_B is Gregorius's test on four of those bits (GDC 2013,
//    "IsMinkowskiFace"): the ends of each arc lie on opposite sides of the other's circle, and
//    on the sides that put the two circles' meeting point inside both arcs;
//  - a face normal's cell in the other map (its support vertex) is the cell whose every side
//    it is not beyond: per cell, an AND of the masks of its arcs.
// Each sign is the one the walks take (side(): the same product, the same filter), and the
// tables are used only when every one of them clears kSideFilter: then no normal lies on an
// arc's circle of the other map (no tie: every facet is a face with a vertex or a
// parallelogram), and the result is the exact overlay, as the walks' is. Where some sign is
// not certain (a tie, or too near one), the walks answer.
#include <algorithm>

#include "sum/overlay.hpp"

namespace minksum::detail {

namespace {

using Eigen::Vector3d;

// Vectors as columns for side_masks, padded with zeros to a multiple of 8 entries.
struct Columns {
  alignas(64) double x[64], y[64], z[64];
};

void columns(const Vector3d* v, int n, Columns& out) {
  for (int k = 0; k < n; ++k) out.x[k] = v[k].x(), out.y[k] = v[k].y(), out.z[k] = v[k].z();
  for (int k = n; k < (n + 7) / 8 * 8; ++k) out.x[k] = out.y[k] = out.z[k] = 0;
}

// The lowest n bits.
inline std::uint64_t low_bits(int n) { return n >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << n) - 1; }

// The cell of map m each of the other operand's n normals lies in (its support vertex): the
// cell whose every side it is not beyond, read from left[e], the normals left of arc e (on its
// pole's side). False unless each normal has exactly one cell (a map bent by rounding).
bool cells_of(const MapLayout& m, const std::uint64_t* left, int n, std::vector<Location>& loc) {
  const int cells = int(m.cell_start.size()) - 1;
  std::uint64_t seen = 0;
  loc.resize(size_t(n));
  for (int c = 0; c < cells; ++c) {
    std::uint64_t inside = low_bits(n);
    for (int k = m.cell_start[c]; k < m.cell_start[c + 1]; ++k) {
      const int arc = m.cell_slot[k].arc;  // beyond it: left of an arc leaving c, right of one entering
      inside &= arc >= 0 ? ~left[arc] : left[~arc];
    }
    if (inside & seen) return false;
    seen |= inside;
    for (; inside; inside &= inside - 1) loc[size_t(__builtin_ctzll(inside))] = {Location::Cell, c};
  }
  return seen == low_bits(n);
}

}  // namespace

bool Overlay::locate_small(const Placed& A, const Placed& B) {
  const MapLayout &ma = *A.m, &mb = *B.m;
  const int arcs_a = A.s->arcs, arcs_b = B.s->arcs, faces_a = A.s->faces, faces_b = B.s->faces;
  // The side of every normal of one operand against every arc of the other, c . G, the
  // products the walks' side() takes: left_of_b[e], the normals of A left of B's arc e;
  // b_left_of[e], the normals of B left of A's arc e, and (the same signs by rows)
  // left_of_a[g], the arcs of A that B's normal g lies left of.
  Columns p, g;
  columns(A.c, arcs_a, p), columns(B.g, faces_b, g);
  if (!side_masks(p.x, p.y, p.z, arcs_a, g.x, g.y, g.z, faces_b, kSideFilter, left_of_a) ||
      !side_masks(g.x, g.y, g.z, faces_b, p.x, p.y, p.z, arcs_a, kSideFilter, b_left_of))
    return false;
  columns(A.g, faces_a, p), columns(B.c, arcs_b, g);
  if (!side_masks(p.x, p.y, p.z, faces_a, g.x, g.y, g.z, arcs_b, kSideFilter, left_of_b)) return false;
  // Every normal's cell in the other map.
  if (!cells_of(mb, left_of_b, faces_a, loc_b) || !cells_of(ma, b_left_of, faces_b, loc_a)) return false;
  // Per face f of A, the arcs of A it is the left (right) face of.
  std::uint64_t of_l[64], of_r[64];
  std::fill(of_l, of_l + faces_a, 0), std::fill(of_r, of_r + faces_a, 0);
  for (int ea = 0; ea < arcs_a; ++ea)
    of_l[ma.arc[ea].L] |= std::uint64_t(1) << ea, of_r[ma.arc[ea].R] |= std::uint64_t(1) << ea;
  // The crossings, per arc e_B: the arcs of A whose circles separate its ends (up: G_L(e_B) is
  // left of them), whose ends e_B's circle separates, and whose circles meet e_B's inside both
  // arcs: G_L(e_B) left of e_A's circle exactly when G_R(e_A) is left of e_B's.
  std::uint64_t crossed = 0;
  crossings.clear();
  for (int eb = 0; eb < arcs_b; ++eb) {
    const MapLayout::Arc& b = mb.arc[eb];
    const std::uint64_t up = left_of_a[b.L], separate = up ^ left_of_a[b.R];
    if (!separate) continue;
    std::uint64_t l = 0, r = 0;  // the arcs of A whose face L (R) is left of e_B
    for (std::uint64_t x = left_of_b[eb]; x; x &= x - 1) {
      const int f = __builtin_ctzll(x);
      l |= of_l[f], r |= of_r[f];
    }
    for (std::uint64_t x = separate & (l ^ r) & ~(up ^ r); x; x &= x - 1) {
      const int ea = __builtin_ctzll(x);
      add_crossing(crossings, ea, eb, up >> ea & 1);
      crossed |= std::uint64_t(1) << ea;
    }
  }
  // The tables agree with themselves (they can only disagree on a map bent by rounding): an
  // arc of A no arc of B crosses joins two normals in one cell of B.
  for (int ea = 0; ea < arcs_a; ++ea)
    if (!(crossed >> ea & 1) && loc_b[size_t(ma.arc[ea].L)].id != loc_b[size_t(ma.arc[ea].R)].id) return false;
  return true;
}

}  // namespace minksum::detail
