// The Gauss-map overlay of two placed shapes (internal; overlay.cpp).
#pragma once

#include <Eigen/Geometry>
#include <utility>
#include <vector>

#include <minksum/sum.hpp>

#include "shape_data.hpp"

namespace minksum::detail {

/// One operand in the world frame: its normals, arc directions and vertices rotated (and for
/// -B negated) into scratch, or the body arrays themselves under the identity. -B is read as
/// a polytope of its own: vertices, normals and directions negated, each arc's faces swapped
/// (u and v stay), face loops reversed.
struct Placed {
  const ShapeData* s = nullptr;
  bool negate = false;  ///< this is -B
  bool moves = false;   ///< B (or -B): the operand the perturbation turns
  const double *nx, *ny, *nz, *dx, *dy, *dz, *px, *py, *pz;
  int L(int e) const { return negate ? s->arc[e].R : s->arc[e].L; }
  int R(int e) const { return negate ? s->arc[e].L : s->arc[e].R; }
  Eigen::Vector3d normal(int f) const { return {nx[f], ny[f], nz[f]}; }
  Eigen::Vector3d dir(int e) const { return {dx[e], dy[e], dz[e]}; }
  Eigen::Vector3d point(int v) const { return {px[v], py[v], pz[v]}; }
  /// Which side of this operand's arc e (its great circle) the normal f of `other` lies on:
  /// +-1 decided (the margin, else exactly); +-2 exactly on the circle, decided by the
  /// perturbation; 0 undecided even so.
  int side(int e, const Placed& other, int f, double tol) const;
};

/// World-frame copies of one operand's arrays (per thread, reused).
struct PlacedBuffers {
  std::vector<double> n[3], d[3], p[3];
};

/// Places shape s by `pose` (negated for -B): rotates into `buf` only what the pose changes.
void place(const ShapeData& s, const Eigen::Isometry3d& pose, bool negate, PlacedBuffers& buf, Placed& out);

/// A proper crossing of arc ea of A with arc eb of B; up: s1 = sign(d_A . N_B,left) > 0.
struct Crossing {
  int ea, eb;
  bool up;
};

/// Where a normal lies in the other operand's Gauss map (overlay.cpp).
struct Feature;

/// The overlay's scratch (one per thread: a sum allocates only while it grows) and its steps.
struct OverlayScratch {
  // Facets before numbering: normal, whether its offset is the largest over the loop, and its
  // loop of vertex pairs (pi, pj) from start[k] to start[k + 1].
  std::vector<Eigen::Vector3d> normal;
  std::vector<char> loose_offset;
  std::vector<int> start, pi, pj;
  std::vector<Crossing> crossings;
  std::vector<int> loc_b, loc_a, coincide, queue;
  std::vector<char> clean_b, clean_a, walked;
  std::vector<int> bucket, order, fill, stamp, number_of_j, number, js;
  struct Dir {
    Eigen::Vector3d m;
    int after;
    bool from_a;
  };
  std::vector<Dir> dirs;
  std::vector<std::pair<int, Dir>> keyed;
  bool dedupe = false, perturbed = false;

  /// A (+) B into out; false if some step failed (the caller runs the hull corrector).
  bool run(const Placed& A, const Placed& B, double tol, MinkowskiSum& out);

 private:
  void begin_facet(const Eigen::Vector3d& n, bool loose);
  void add_pair(int i, int j) { pi.push_back(i), pj.push_back(j); }
  void end_facet();
  void sector_loop(const Placed& A, const Feature& fa, const Placed& B, const Feature& fb, const Eigen::Vector3d& n);
  bool number_and_write(const Placed& A, const Placed& B, MinkowskiSum& out);
};

/// Every directed edge of the loops appears once, and its reverse once: a closed 2-manifold.
bool closed_manifold(const MinkowskiSum& m);

/// Every facet's vertices (i, j) are extreme along its normal in A and in B (a_i has no
/// neighbour higher, nor b_j): a proof that each plane supports A (+) B.
bool planes_support(const Placed& A, const Placed& B, const MinkowskiSum& m);

}  // namespace minksum::detail
