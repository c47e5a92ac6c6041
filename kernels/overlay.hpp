// The Gauss-map overlay of two placed shapes (internal; overlay.cpp).
#pragma once

#include <minksum/sum.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <utility>
#include <vector>

#include "shape_data.hpp"

namespace minksum::detail {

/// One operand in the world frame: its normals, slot directions and vertices rotated (and for
/// -B negated) into scratch, or the body arrays themselves under the identity. -B is read as
/// a polytope of its own: vertices, normals and directions negated, each arc's faces swapped
/// (u and v stay), face loops reversed.
struct Placed {
  const ShapeData* s = nullptr;
  bool negate = false;  ///< this is -B
  bool moves = false;   ///< B (or -B): the operand the perturbation turns
  const double *nx, *ny, *nz, *sx, *sy, *sz, *px, *py, *pz;
  Eigen::Matrix3d linear;  ///< the pose's rotation (negated for -B)
  bool turned = false;     ///< linear is not the identity
  int L(int e) const { return negate ? s->arc[e].R : s->arc[e].L; }
  int R(int e) const { return negate ? s->arc[e].L : s->arc[e].R; }
  Eigen::Vector3d normal(int f) const { return {nx[f], ny[f], nz[f]}; }
  /// Arc e's pole N_L x N_R (a positive multiple of its edge).
  Eigen::Vector3d pole(int e) const {
    const int k = s->arc_slot[e];
    return {sx[k], sy[k], sz[k]};
  }
  Eigen::Vector3d point(int v) const { return {px[v], py[v], pz[v]}; }
  /// Arc e's edge p_v - p_u (zero for a prism's zero-length edges), turned from the body frame:
  /// a translation far larger than the shape would leave only rounding in the placed points.
  Eigen::Vector3d edge(int e) const {
    const int v = s->cell_vertex[s->arc[e].v], u = s->cell_vertex[s->arc[e].u];
    const Eigen::Vector3d d(s->px[v] - s->px[u], s->py[v] - s->py[u], s->pz[v] - s->pz[u]);
    return turned ? Eigen::Vector3d(linear * d) : d;
  }
  /// Which side of this operand's arc e (its great circle, pole N_L x N_R) the normal f of
  /// `other` lies on, when pole_e . N_f is within the filter: +-1 exactly; +-2 exactly on the
  /// circle, decided by the perturbation; 0 undecided even so.
  int exact_side(int e, const Placed& other, int f) const;
  /// Whether the normal f of `other` lies beyond slot k (its cell across is higher along it),
  /// when the slot's direction . N_f is within the filter: +-1, +-2 or 0 as exact_side.
  int exact_beyond(int k, const Placed& other, int f) const {
    const int a = s->cell_slot[k].arc;
    return a >= 0 ? exact_side(a, other, f) : -exact_side(~a, other, f);
  }
};

/// World-frame copies of one operand's arrays (per thread, reused).
struct PlacedBuffers {
  std::vector<double> n[3], d[3], p[3];
};

/// Places shape s by `pose` (negated for -B): rotates into `buf` only what the pose changes.
void place(const ShapeData& s, const Eigen::Isometry3d& pose, bool negate, PlacedBuffers& buf, Placed& out);

/// A proper crossing of arc ea of A with arc eb of B; up: s1 = sign(d_A . N_B,left) > 0.
struct Crossing {
  int ea, eb, up;
};

/// Where a normal lies in the other operand's Gauss map (overlay.cpp).
struct Feature;

/// The overlay's scratch (one per thread: a sum allocates only while it grows) and its steps.
class OverlayScratch {
 public:
  /// A (+) B into out; false if some step failed (the caller runs the hull corrector).
  bool run(const Placed& A, const Placed& B, MinkowskiSum& out);

  /// A direction leaving a facet normal towards the normal m along an arc; `after` is the cell
  /// counter-clockwise after it (seen from outside).
  struct Dir {
    Eigen::Vector3d m;
    int after;
    bool from_a;
  };

 private:
  void begin_facet(MinkowskiSum& out, const Eigen::Vector3d& n, bool loose);
  void add_pair(int i, int j);
  void end_facet();
  void grow();
  static constexpr std::uint64_t kEmpty = ~std::uint64_t(0);
  bool face_facets(const Placed& A, const Placed& B, MinkowskiSum& out);
  void crossing_facets(const Placed& A, const Placed& B, MinkowskiSum& out);
  void sector_loop(const Placed& A, const Feature& fa, const Placed& B, const Feature& fb,
                   const Eigen::Vector3d& n, MinkowskiSum& out);
  bool number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out);

  std::vector<int> loc_b, loc_a, coincide, queue, hint;  // face normals' cells, faces in order
  std::vector<char> clean_b, clean_a, walked;            // no side of that cell was 0
  std::vector<Crossing> crossings;
  // Facets before numbering: a loop of provisional vertex ids per facet (start[k] ..
  // start[k + 1]), whether its offset is the largest over the loop, and the hash of the pairs
  // (key i 2^32 + j) giving the ids.
  std::vector<int> start, loop;  // sized before the facets are written: nf facets, nl entries
  std::vector<char> loose;
  int nf = 0, nl = 0;
  std::vector<std::uint64_t> slot_key, id_key;
  std::vector<int> slot_id, bucket, fill, order, final_id;
  unsigned mask = 0, shift = 58;  // table size - 1; 64 - log2(size)
  std::vector<Dir> dirs;
  std::vector<std::pair<int, Dir>> keyed;
  bool dedupe = false, perturbed = false;
  bool map_normals = false;  // crossing normals from the poles, every offset the loop's largest
};

/// Every directed edge of the loops appears once, and its reverse once: a closed 2-manifold.
bool closed_manifold(const MinkowskiSum& m);

/// Every facet's vertices (i, j) are extreme along its normal in A and in B (a_i has no
/// neighbour higher, nor b_j): a proof that each plane supports A (+) B.
bool planes_support(const Placed& A, const Placed& B, const MinkowskiSum& m);

}  // namespace minksum::detail
