// The prepared form of a convex shape (internal): the polytope's Gauss map in flat arrays.
#pragma once

#include <minksum/shape.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

#include "core/predicates.hpp"

namespace minksum::detail {

/// The adjacency of a Gauss map (Barki et al. 2009; Fogel & Halperin 2007): face normals are
/// points of the unit sphere, each edge an arc between the normals of its two faces, each
/// vertex a cell bounded by the arcs of its edges. Every cyclic list runs counter-clockwise
/// seen from outside. A shape keeps two layouts: its own, and that of -B (every normal negated:
/// the antipodal map reverses every cyclic list and swaps each arc's faces), which a
/// difference A (-) B reads.
struct MapLayout {
  /// An arc: its cells u, v (the normals on u's side have p_u higher than p_v) and its faces
  /// L, R (L's loop walks u -> v); the pole G_L x G_R is a positive multiple of p_v - p_u.
  struct Arc {
    int u, v, L, R;
  };
  /// One step around a cell: the arc (~arc when the cell is the arc's v), the cell across it,
  /// and the face after it (a corner of the cell, between this arc and the next).
  struct Slot {
    int arc, next, face;
  };
  std::vector<Arc> arc;
  std::vector<int> cell_start;  // per cell (cells + 1): its slots in cell_slot
  std::vector<Slot> cell_slot;  // counter-clockwise around each cell
  std::vector<int> slot_twin;   // per slot: the same arc's slot in the cell across
  std::vector<int> arc_slot;    // per arc e: its slot in cell u (2e) and in cell v (2e + 1)
  std::vector<int> loop_start;  // per face (faces + 1): its loop
  std::vector<int> loop_cell;   // the face's cells, counter-clockwise
  std::vector<int> loop_arc;    // arc k of a loop joins its cells k and k + 1
  std::vector<int> loop_face;   // the face across arc k
  std::vector<int> loop_slot;   // the slot of arc k in cell k (the face follows it there)
  std::vector<int> loop_least;  // per face: where in its loop its smallest vertex is
};

/// A prepared convex polytope. A flat polygon of K vertices is the limit of a thin prism: K + 2
/// faces (top, bottom, one side normal per edge), 2K cells (a top and a bottom copy of each
/// vertex) and 3K arcs (top edges, bottom edges, and one zero-length edge per vertex), so that
/// every arc is shorter than pi.
struct ShapeData {
  /// What a builder made: a box or a triangle keeps its own form, so that queries take the
  /// box-box and box-triangle paths (and their caches) on it. A point (a sphere's core) or a
  /// segment (a capsule's) has its vertices alone: no Gauss map, no faces (the query reads them
  /// through its own view, rounded.cpp).
  enum class Kind : std::uint8_t { General, Box, Triangle, Point, Segment } kind = Kind::General;
  /// Whether the core is a polytope with faces (general, box, triangle), prepared as one.
  bool has_faces() const { return kind != Kind::Point && kind != Kind::Segment; }
  Box box;                                       // shape_from_box's box (body frame)
  Triangle triangle;                             // shape_from_triangle's triangle (body frame)
  ConvexPolytope polytope;                       // a built shape's own polytope (body frame)
  const ConvexPolytope* polytope_ref = nullptr;  // the polytope prepared: &polytope, or the caller's
  /// Unique per preparation (prepare draws it): what the sum's memos of exact answers are
  /// kept for across calls (Overlay::run), where an address could be reused.
  std::uint64_t id = 0;
  int faces = 0, arcs = 0, cells = 0;
  /// Gauss normals, the only input of the map's predicates: each face's exact Newell normal
  /// made canonical (canonical_direction), so that exactly parallel faces of any two shapes
  /// have the same vector where it is a double vector; else rounded once, its exact value in
  /// gauss_terms (gauss_normal).
  std::vector<Eigen::Vector3d> gauss;
  std::vector<std::uint8_t> gauss_nonzero;  // per face: bit k set iff component k of its Gauss normal is not 0
  /// Where a face's exact normal is not a double vector (rounded coordinates), the predicates
  /// read it exactly (gauss_normal): Stored, component k of face f is the expansion
  /// gauss_terms[gauss_term_start[3f + k] ... gauss_term_start[3f + k + 1]); OnDemand, it is
  /// computed from the face's loop (a solid's: its cells are its vertices) and
  /// gauss_exponent[f]. Both scaled as gauss[f] is.
  std::vector<GaussKind> gauss_kind;
  std::vector<double> gauss_terms;
  std::vector<int> gauss_term_start;  // 3 faces + 1 entries
  std::vector<int> gauss_exponent;
  bool any_rounded = false;  ///< some face is not GaussKind::Exact
  /// The exact normal of face f: the doubles of gauss[f], its stored terms, or computed into
  /// `local` (3 kMaxGaussTerms doubles).
  ExactVector exact_normal(int f, double* local) const {
    const size_t F = size_t(f);
    if (gauss_kind[F] == GaussKind::Exact) return exact_vector(gauss[F]);
    if (gauss_kind[F] == GaussKind::OnDemand) {
      const int first = map[0].loop_start[F], n = map[0].loop_start[F + 1] - first;
      return exact_gauss_normal(&map[0].loop_cell[size_t(first)], n, px.data(), py.data(), pz.data(),
                                gauss_exponent[F], local);
    }
    const int* at = &gauss_term_start[3 * F];
    const double* t = gauss_terms.data();
    return {{t + at[0], t + at[1], t + at[2]}, {at[1] - at[0], at[2] - at[1], at[3] - at[2]}, 1.0};
  }
  /// The exact normal of face f to 106 bits: an OnDemand face's from its Newell products in
  /// double-double (no expansions), else from its exact normal's terms.
  NearVector near_normal(int f) const {
    const size_t F = size_t(f);
    if (gauss_kind[F] == GaussKind::OnDemand) {
      const int first = map[0].loop_start[F], n = map[0].loop_start[F + 1] - first;
      return near_gauss_normal(&map[0].loop_cell[size_t(first)], n, px.data(), py.data(), pz.data(), gauss_exponent[F]);
    }
    double local[3 * kMaxGaussTerms];
    return near_vector(exact_normal(f, local));
  }
  /// Whether face f's exact normal is not gauss[f] itself.
  bool rounded_normal(int f) const { return gauss_kind[size_t(f)] != GaussKind::Exact; }
  std::vector<double> nx, ny, nz;           // unit face normals (the sums' planes)
  MapLayout map[2];                         // [0] the shape's own, [1] that of -B
  std::vector<Eigen::Vector3d> pole[2];     // per arc, in each layout: G_L x G_R (for -B: -G_R x -G_L)
  /// Per arc: bit k set iff component k of its pole is 0 for want of a term (each product of
  /// that 2 x 2 minor has a zero factor): with gauss_nonzero, a sign that is 0 without
  /// arithmetic (axis-aligned and prism normals).
  std::vector<std::uint8_t> pole_zero;
  std::vector<int> cell_vertex;    // per cell: its polytope vertex
  std::vector<int> vertex_cell;    // per vertex: a cell of it (a prism's top copy)
  std::vector<double> px, py, pz;  // polytope vertices
  std::vector<double> ex, ey, ez;  // per arc: its edge p_v - p_u (a prism's zero-length ones: 0)
  double size = 0;                 // largest |coordinate|: the scale of the rounding
  /// The largest sine of the angle between an edge and its arc's pole: rounding (about
  /// 1e-16 / |G_L x G_R|), or faces planar only to a tolerance (a flat polygon's points within
  /// 1e-10 of its plane, a polytope from a mesh).
  double pole_slack = 0;
  /// A bound on what a normal placed on the wrong side of an arc can cost a sum's support
  /// value: per arc, pole_error_bound (large on a sliver whose adjacent faces nearly coincide or
  /// nearly oppose) times its edge's length; the largest over the arcs.
  double support_error = 0;
  /// The largest of those angles (pole_error_bound) over the arcs.
  double pole_error = 0;
  std::vector<Eigen::Vector3d> dir;  // prepare's: per arc p_v - p_u (a prism's zero-length arcs: -normal x width)
};

/// The angle (a bound) between the pole G_L x G_R rounded in double and the exact cross product
/// of the two normals, which the predicates follow: each component of the rounded product is
/// within 2 eps |G_L| |G_R| of the exact one (4e-16 |G_L| |G_R| in all; 1e-15 leaves a margin).
/// Large on a short arc, or one between faces that nearly oppose.
inline double pole_error_bound(const Eigen::Vector3d& gl, const Eigen::Vector3d& gr, const Eigen::Vector3d& pole) {
  const double c2 = pole.squaredNorm();
  return c2 > 0 ? 1e-15 * std::sqrt(gl.squaredNorm() * gr.squaredNorm() / c2) : HUGE_VAL;
}

/// The library's access to a shape's data.
struct ShapeAccess {
  /// The prepared data (nullptr if the shape is empty).
  static const ShapeData* data(const ConvexShape& s) { return s.data_.get(); }
  /// Makes `out` hold `data` (its radius 0).
  static void set(std::shared_ptr<const ShapeData> data, ConvexShape& out) {
    out.data_ = std::move(data), out.radius_ = 0;
  }
  /// Sets the radius swept around `s`'s core.
  static void set_radius(ConvexShape& s, double radius) { s.radius_ = radius; }
};

/// Bit k set iff component k of v is not 0.
inline std::uint8_t nonzero_mask(const Eigen::Vector3d& v) {
  return std::uint8_t((v.x() != 0) | (v.y() != 0) << 1 | (v.z() != 0) << 2);
}

/// Bit k set iff component k of G_L x G_R is 0 for want of a term (see ShapeData::pole_zero),
/// from the normals' nonzero_masks: one table read (a turned map's poles, every sum).
inline std::uint8_t pole_zero_mask(std::uint8_t l, std::uint8_t r) {
  struct Table {
    std::uint8_t at[64];
    constexpr Table() : at() {
      for (int m = 0; m < 64; ++m) {
        const auto none = [m](int a, int b) {  // l_a r_b and l_b r_a both lack a factor
          return !((m >> a & 1) && (m >> (3 + b) & 1)) && !((m >> b & 1) && (m >> (3 + a) & 1));
        };
        at[m] = std::uint8_t(none(1, 2) | none(2, 0) << 1 | none(0, 1) << 2);
      }
    }
  };
  static constexpr Table kTable;
  return kTable.at[l | r << 3];
}

/// Prepares p into `out`, reusing its capacity (the convenience entry points keep one per
/// thread); InvalidMesh when p breaks the ConvexPolytope contract (see shape_from_polytope).
/// The layout of -B only if `negated_layout` (a shape has both; a sum's A needs its own only).
Status prepare(const ConvexPolytope& p, ShapeData& out, bool negated_layout = true);

}  // namespace minksum::detail
