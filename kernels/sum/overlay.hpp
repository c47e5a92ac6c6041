// The Gauss-map overlay of two placed shapes (internal; overlay.cpp).
#pragma once

#include <minksum/sum.hpp>

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "geometry/rigid.hpp"
#include "shape/shape_data.hpp"
#include "sum/pair_numbering.hpp"

namespace minksum::detail {

/// The static filter of every side of a normal against an arc, c . G: |G| components are at
/// most 2 (canonical normals, turned), so c . G is within 192 ulp(1) ~ 2.2e-14 of
/// det(G, G_L, G_R); a rounded normal's own rounding (kRoundedNormal per component, unturned)
/// adds at most 1.8e-13; 4e-13 leaves a margin.
constexpr double kSideFilter = 4e-13;

/// The most arcs an operand of the small overlay (Overlay::locate_small) has.
constexpr int kSmallArcs = 64;

/// Whether the small overlay's tables are the cheaper way to locate a and b: at most kSmallArcs
/// arcs each, and F_A E_B + F_B E_A products at most 24 per walk step (E_A + E_B). Measured on
/// an AVX-512 EPYC (two sphere polytopes of n points, B turned): the tables are faster to 24
/// products a step (n = 14: 0.89-0.99 us against 1.03), even at 28 (n = 16), slower from 36
/// (n = 20: 1.80 against 1.61); on AVX2, with half the lanes, the products cost more.
inline bool small_overlay_fits(const ShapeData& a, const ShapeData& b) {
  return a.arcs <= kSmallArcs && b.arcs <= kSmallArcs && a.faces * b.arcs + b.faces * a.arcs <= 24 * (a.arcs + b.arcs);
}

/// For each vector g_j (j < m), bit i of out[j] set iff p_i . g_j > filter, for n <= 64 vectors
/// p_i (columns px, py, pz padded to a multiple of 8); false at the first g_j with some
/// |p_i . g_j| <= filter (kernels/simd/side_masks.hpp, the active ISA).
bool side_masks(const double* px, const double* py, const double* pz, int n, const double* gx, const double* gy,
                const double* gz, int m, double filter, std::uint64_t* out);

/// One operand of a sum. The overlay is computed in A's body frame: the structure of a sum
/// depends only on the relative rotation of its operands, and two shapes under one rotation
/// (copies, mirrored pairs, aligned boxes turned together) keep every tie exact there. So A's
/// Gauss normals and poles are the prepared ones, B's are turned by R_A^T R_B (exactly the
/// identity when both poses have the same rotation), and -B reads the shape's second layout
/// (MapLayout). The output is in the world frame: vertices placed by each pose, normals and
/// edges turned from the body frame by `world`.
struct Placed {
  const ShapeData* s = nullptr;
  const MapLayout* m = nullptr;
  bool negate = false;            ///< this is -B
  bool own_frame = true;          ///< the overlay frame is the body frame (frame = +-I)
  const Eigen::Vector3d* g;       ///< Gauss normals in the overlay frame (the predicates' input)
  const Eigen::Vector3d* c;       ///< per arc: its pole G_L x G_R in the overlay frame
  const std::uint8_t* g_nonzero;  ///< per face: ShapeData::gauss_nonzero of g
  const std::uint8_t* c_zero;     ///< per arc: ShapeData::pole_zero of c
  const double *px, *py, *pz;     ///< vertices in the world frame
  bool rounded = false;           ///< some normal has exact terms (ShapeData::gauss_terms) the predicates read
  bool is_a = false;              ///< this is A (the overlay's frame)
  /// A's only: per face and way (2 f + same way), the face of B last found near its line and
  /// whether it lies exactly on it (2 g + on line; -1: none yet): the overlay's memo of the
  /// rounded ties (overlay.cpp, collinear).
  int* collinear = nullptr;
  /// Per face: its exact normal, once computed (GaussKind::OnDemand: 3 kMaxGaussTerms doubles,
  /// and 3 counts, -1 until then), for the rest of the overlay (its memo; overlay.cpp, run).
  double* exact_terms = nullptr;
  std::int8_t* exact_count = nullptr;
  Rigid world;                    ///< body -> world pose (negated for -B)
  Eigen::Matrix3d frame;          ///< body -> overlay frame rotation (negated for -B)
  /// Per face: its exact normal to 106 bits, unsigned (the sign of -B applied on reading), once
  /// computed for this shape (ShapeData::id): the overlay's memo, kept as exact_terms is.
  struct NearMemo {
    NearVector v;
    std::uint64_t shape;
  };
  NearMemo* near_memo = nullptr;
  int L(int e) const { return m->arc[e].L; }
  int R(int e) const { return m->arc[e].R; }
  const Eigen::Vector3d& gauss(int f) const { return g[f]; }
  const Eigen::Vector3d& pole(int e) const { return c[e]; }
  Eigen::Vector3d point(int v) const { return {px[v], py[v], pz[v]}; }
  /// Whether normal f is read from its exact terms (not g[f] itself).
  bool rounded_normal(int f) const { return rounded && s->rounded_normal(f); }
  /// Normal f exactly: its terms (negated for -B; computed into `local`, 3 kMaxGaussTerms
  /// doubles, where they are not stored), or g[f].
  ExactVector exact(int f, double* local) const {
    if (!rounded_normal(f)) return exact_vector(g[f]);
    ExactVector x;
    if (s->gauss_kind[size_t(f)] == GaussKind::OnDemand && exact_count) {
      double* t = exact_terms + size_t(f) * 3 * kMaxGaussTerms;
      std::int8_t* n = exact_count + 3 * size_t(f);
      if (n[0] < 0) {
        x = s->exact_normal(f, t);
        for (int k = 0; k < 3; ++k) n[k] = std::int8_t(x.count[k]);
      } else {
        x = {{t, t + kMaxGaussTerms, t + 2 * kMaxGaussTerms}, {n[0], n[1], n[2]}, 1.0};
      }
    } else {
      x = s->exact_normal(f, local);
    }
    x.sign = negate ? -1.0 : 1.0;
    return x;
  }
  /// Normal f to about 106 bits (orient_near's input), from the memo where there is one.
  NearVector near(int f) const {
    if (!rounded_normal(f)) return near_vector(exact_vector(g[f]));  // (g[f] is signed already)
    NearVector x;
    if (near_memo && near_memo[f].shape == s->id) {
      x = near_memo[f].v;
    } else {
      x = s->near_normal(f);
      if (near_memo) near_memo[f] = {x, s->id};
    }
    if (negate)
      for (int k = 0; k < 3; ++k) x.hi[k] = -x.hi[k], x.lo[k] = -x.lo[k];
    return x;
  }
  /// Face f's unit normal in the world frame.
  Eigen::Vector3d unit(int f) const { return world.turn(Eigen::Vector3d(s->nx[f], s->ny[f], s->nz[f])); }
  /// Arc e's edge p_v - p_u in the world frame (zero for a prism's zero-length edges), turned
  /// from the body frame: a translation far larger than the shape would leave only rounding in
  /// the placed points.
  Eigen::Vector3d edge(int e) const { return world.turn(Eigen::Vector3d(s->ex[e], s->ey[e], s->ez[e])); }
};

/// Copies of one operand's arrays turned or moved (per thread, reused).
struct PlacedBuffers {
  std::vector<Eigen::Vector3d> g, c;
  std::vector<std::uint8_t> g_nonzero, c_zero;
  std::vector<double> p[3];
};

/// Places shape s by `pose` (negated for -B), its Gauss map turned into the overlay frame by
/// `frame` (A: the identity; B: R_A^T R_B): turns into `buf` only what the pose changes.
void place(const ShapeData& s, const Eigen::Isometry3d& pose, const Eigen::Matrix3d& frame, bool negate,
           PlacedBuffers& buf, Placed& out);

/// Where a normal of one operand lies in the other's Gauss map, exactly: inside a cell, inside
/// an arc, or on a face normal.
struct Location {
  enum Kind : std::int32_t { Cell, Arc, Face } kind;
  std::int32_t id;
};

/// A proper crossing of arc ea of A with arc eb of B; up: G_L(eb) lies on the positive side of
/// ea's pole; its facet in the result (-1: none, a flat operand's degenerate one).
struct Crossing {
  int ea, eb;
  bool up;
  int facet = -1;
};

/// Appends crossing (ea, eb, up), field by field: a whole-struct copy would read its bytes back
/// at once, stalling on the byte just stored (store forwarding fails).
inline void add_crossing(std::vector<Crossing>& out, int ea, int eb, bool up) {
  Crossing& x = out.emplace_back();
  x.ea = ea, x.eb = eb, x.up = up;
}

/// The overlay's scratch (one per thread: a sum allocates only while it grows) and its steps.
class Overlay {
 public:
  /// A (+) B into out, the parts asked for; false if a step failed (the caller runs the hull
  /// corrector).
  bool run(Placed& A, Placed& B, MinkowskiSum& out, SumParts parts);

  /// Steps 1 and 2 of run (overlay.cpp): every face normal located in the other map, and the
  /// proper crossings of arcs; by the small tables (overlay_small.cpp) where `small` and they
  /// answer, else by the walks. False if a step failed.
  bool locate(Placed& A, Placed& B, bool small);
  /// What locate found: A's normals in B's map, B's in A's, and the crossings.
  const std::vector<Location>& a_normals() const { return loc_b; }
  const std::vector<Location>& b_normals() const { return loc_a; }  ///< (see a_normals)
  const std::vector<Crossing>& arc_crossings() const { return crossings; }  ///< (see a_normals)
  /// Whether the last locate was answered by the small tables.
  bool by_tables = false;

  /// A direction leaving a facet normal along an arc towards the normal `to`, and the cell
  /// counter-clockwise after it (seen from outside).
  struct Ray {
    int to, after;
  };

 private:
  bool locate_small(const Placed& A, const Placed& B);
  bool walk_a_arcs(const Placed& A, const Placed& B);
  bool locate_b_normals(const Placed& A, const Placed& B);
  bool face_facets(const Placed& A, const Placed& B);
  void crossing_facets(const Placed& A, const Placed& B);
  bool merged_facet(const Placed& A, const Location& fa, const Placed& B, const Location& fb, bool normal_of_a);
  bool number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out);
  bool write_planes(const Placed& A, const Placed& B, MinkowskiSum& out);
  Eigen::Vector3d crossing_normal(const Placed& A, const Placed& B, const Crossing& x, bool& loose_offset,
                                  double& length2) const;
  bool place_rays(const Placed& N, int nf, const Placed& R, const std::vector<Ray>& ref, const Placed& O,
                  const std::vector<Ray>& other, std::vector<int>& sector);
  void begin_facet(const Eigen::Vector3d& n, bool loose, int length);
  void add_pair(int i, int j) { codes[size_t(nl++)] = pairs.code(i, j); }
  void end_facet(bool dedupe);

  std::vector<Location> loc_b, loc_a;  // A's face normals in B's map, B's in A's
  std::vector<int> queue;
  std::vector<int> walked, queued;  // (int: a char store would alias every pointer the loops hold)
  std::vector<Crossing> crossings;
  std::vector<int> b_arc_crossings;  // per arc of B: how many arcs of A cross it, and the last one
  std::vector<int> b_arc_last;
  std::vector<Ray> rays[2];
  std::vector<int> ray_sector;
  struct Turn {
    Eigen::Vector3d c, bound;
  };
  std::vector<Turn> turns;       // place_rays': per ray of the reference, n x r and its permanent
  // locate_small's sign tables (overlay_small.cpp).
  std::uint64_t left_of_a[64], b_left_of[64], left_of_b[64];
  std::vector<int> face_sector;  // per loop position of A: its ray's sector about B's coincident face (place_rays)
  // The memos of exact answers, kept while their shapes are (ShapeData::id; 0: none):
  std::vector<int> collinear;    // Placed::collinear of A, for the pair tie_pair (A, B, B negated)
  std::vector<double> exact_terms[2];  // Placed::exact_terms of A and B, of shapes exact_shape
  std::vector<std::int8_t> exact_count[2];
  std::uint64_t tie_pair[3] = {0, 0, 0}, exact_shape[2] = {0, 0};
  std::uint64_t tie_free_pair[3] = {0, 0, 0};  // and whether the small tables answered that pair in its own frame
  bool tie_free = false;
  bool merged = false;           // some facet merges features (a tie): checked as a closed manifold
  bool dedupe_all = false;       // a flat operand's zero-length arcs repeat vertices
  bool map_normals = false;      // crossing normals from the poles, every offset the loop's largest
  double crossing_slack = 0;     // crossing_normal's: how far edges may stray from their poles
  bool crossing_certain = false;  // and whether the 1e-4 rule alone decides
  // The facets as written: their normals, loops of pair codes (facet k's at facet_start[k] ..
  // facet_start[k + 1]), and whether each one's offset is the largest over its loop.
  std::vector<Eigen::Vector3d> normal;
  std::vector<int> codes, facet_start, loose;
  std::vector<double> length2;       // per crossing: its normal's squared length, then 1 / length
  std::vector<int> loose_crossing;   // write_planes': per crossing, whether its offset is the loop's largest
  int nf = 0, nl = 0;
  PairNumbering pairs;
  std::vector<Placed::NearMemo> near[2];  // Placed::near_memo of A and B (each entry names its shape)
};

/// Each x of `length2` (squared lengths of normals) replaced by 1 / sqrt(x).
void unit_normals(std::vector<double>& length2);

/// Every facet's vertices (i, j) (SumParts::Planes: its pair) are extreme along its normal in
/// A and in B (a_i has no neighbour higher, nor b_j): a proof that each plane supports A (+) B.
bool planes_support(const Placed& A, const Placed& B, const MinkowskiSum& m);

}  // namespace minksum::detail
