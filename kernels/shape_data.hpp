// The prepared form of a convex shape (internal): the polytope's Gauss map in flat arrays.
#pragma once

#include <minksum/shape.hpp>

#include <vector>

namespace minksum::detail {

/// The Gauss map of a convex polytope in its body frame (Barki et al. 2009; Fogel & Halperin
/// 2007): face normals are points of the unit sphere, each edge an arc between the normals of
/// its two faces, each vertex a cell bounded by the arcs of its edges. A flat polygon of K
/// vertices is the limit of a thin prism (as sum_fast did): K + 2 faces (top, bottom, one side
/// normal per edge), 2K cells (a top and a bottom copy of each vertex) and 3K arcs (top edges,
/// bottom edges, and one zero-length edge per vertex), so that every arc is shorter than pi.
struct ShapeData {
  /// An arc: cells on either side (u where n . (p_v - p_u) < 0) and faces at its ends (L's
  /// loop walks u -> v, R's walks v -> u); N_L x N_R is a positive multiple of p_v - p_u.
  struct Arc {
    int u, v, L, R;
  };
  ConvexPolytope polytope;           // a built shape's own polytope (body frame)
  const ConvexPolytope* polytope_ref = nullptr;  // the polytope prepared: &polytope, or the caller's
  int faces = 0, arcs = 0, cells = 0;
  std::vector<double> nx, ny, nz;    // unit face normals
  std::vector<Arc> arc;
  std::vector<int> cell_vertex;      // per cell: its polytope vertex
  std::vector<int> vertex_cell;      // per vertex: a cell of it (a prism's top copy)
  std::vector<int> loop_start;       // per face (faces + 1): its loop in loop_cell, loop_arc
  std::vector<int> loop_cell;        // face loops as cells, counter-clockwise from outside
  std::vector<int> loop_arc;         // arc k of a loop joins its cells k and k + 1
  std::vector<int> loop_face;        // the face across arc k of a loop
  std::vector<int> loop_least;       // per face: where in its loop its smallest vertex is
  /// One arc of a cell, read from it: the arc (~arc when the cell is the arc's v) and the cell
  /// across it. Its direction, read from the cell, is the arc's pole N_L x N_R (from v, its
  /// negation), a positive multiple of p_next - p_cell: the normal n lies beyond the arc (the
  /// cell across is higher along n) iff direction . n > 0. The pole is computed from the very
  /// normals the exact predicate reads, so a float sign that clears the filter is the exact one.
  struct Slot {
    int arc, next;
  };
  std::vector<int> cell_start;       // per cell (cells + 1): its slots
  std::vector<Slot> cell_slot;
  std::vector<double> sx, sy, sz;    // per slot: its direction (the pole, signed)
  std::vector<int> arc_slot, arc_slot_v;  // per arc: its slot in cell u (direction +pole) and in v
  std::vector<double> px, py, pz;    // polytope vertices
  double size = 0;                   // largest |coordinate|: the scale of the rounding errors
  /// The largest sine of the angle between an edge and its arc's pole: rounding (about
  /// 1e-16 / |N_L x N_R|), or faces planar only to a tolerance (Qhull's merged facets, a
  /// flat polygon's points within 1e-10 of its plane).
  double pole_slack = 0;
  std::vector<int> fill, side_used;  // scratch of prepare
  std::vector<Eigen::Vector3d> dir;  // scratch of prepare: per arc p_v - p_u (a prism's zero-length arcs: -normal x width)
};

/// Writes every slot's direction: arc e's pole N_L x N_R from the normals (nx, ny, nz) at its
/// slot in u, the negation at its slot in v (swap: L and R exchanged, as for -B).
void fill_poles(const ShapeData& s, bool swap, const double* nx, const double* ny, const double* nz, double* sx,
                double* sy, double* sz);

/// The library's access to a shape's data.
struct ShapeAccess {
  /// The prepared data (nullptr if the shape is empty).
  static const ShapeData* data(const ConvexShape& s) { return s.data_.get(); }
  /// Makes `out` hold `data`.
  static void set(std::shared_ptr<const ShapeData> data, ConvexShape& out) { out.data_ = std::move(data); }
};

/// Prepares p into `out`, reusing its capacity (the convenience entry points keep one per
/// thread); InvalidMesh when p breaks the ConvexPolytope contract (see shape_from_polytope).
Status prepare(const ConvexPolytope& p, ShapeData& out);

}  // namespace minksum::detail
