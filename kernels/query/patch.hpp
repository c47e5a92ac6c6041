// Contact patches in the plane across a contact normal: convex sets of up to kPatch points seen
// along the normal (a point, a segment or a counter-clockwise polygon), their overlap, the
// witness on it, and a box's set on its level plane. Shared by the proximity queries (the
// witnesses on a patch) and contact_patch; internal.
#pragma once

#include <minksum/query.hpp>

namespace minksum::detail {

// The witnesses on a patch. Where the nearest (or deepest) sets are more than a point (a face
// on a face, an edge on a face, parallel edges), the first pair GJK meets jumps from corner
// to corner as the shapes slide. The witnesses are instead the point of the overlap of A's
// top set and B's bottom set (seen along n) nearest the centre of the smaller one: that centre
// itself while it lies inside the other (a tool resting on a face), and they move continuously.
constexpr int kPatch = 128;  // the most vertices a patch keeps (a larger face: GJK's witnesses)

struct Patch {
  Eigen::Vector2d p[kPatch];
  int size = 0;
};

inline double cross2(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// The vertex after k around x (a compare, not a division: the patch loops run per query).
inline int after(const Patch& x, int k) { return k + 1 == x.size ? 0 : k + 1; }

// Twice the signed area of x (positive counter-clockwise).
double area2(const Patch& x);
// A patch narrower than tol made what it is at that tolerance: a segment or a point.
void settle(Patch& x, double tol);
// Whether the point x lies in the set y (within tol).
bool meets(const Eigen::Vector2d& x, const Patch& y, double tol);
// The overlap of small and large (2 or more points each; within tol): empty where they miss.
void overlap_of(const Patch& small, const Patch& large, double tol, Patch& overlap);
// The overlap of A's set P and B's set Q, as A's set clipped (P's orientation kept).
void overlap_of_sets(const Patch& P, const Patch& Q, double tol, Patch& overlap);
// An overlap without repeated points (a vertex on a clipping line comes out twice), settled.
void tidy(Patch& x, double tol);
// The witness on A's and B's level sets P and Q (see Patch); false where they do not meet.
bool patch_point(const Patch& P, const Patch& Q, double tol, Eigen::Vector2d& x);

// Where a box meets its level along a unit normal: the corner on it, or the first corner of
// the edge or face on it (`base`, corner `code`: bit k set on axis k's + side), and the axes
// across the normal within tau (`free`, `nfree` of them: 0 a corner, 1 an edge, 2 a face).
struct BoxLevel {
  Eigen::Vector3d base;
  int free[2];
  int nfree = 0, code = 0;
};
// Box x's level along the unit m (sign +1: its top, -1: its bottom) without the set itself;
// false for a box narrower than tau in every axis.
inline bool box_level_of(const Box& x, const Eigen::Vector3d& m, double sign, double tau, BoxLevel& L) {
  // The axes across m (within tau over the box) run free; the others sit at the side m points
  // to: a face, an edge or a corner. Corner `code` has bit k set on axis k's + side.
  L.base = x.center, L.nfree = 0, L.code = 0;
  for (int k = 0; k < 3; ++k) {
    const double d = sign * m.dot(x.rotation.col(k));
    if (2 * x.half_extents[k] * std::abs(d) <= tau) {
      if (L.nfree == 2) return false;
      L.free[L.nfree++] = k;
    } else {
      L.base += (d > 0 ? 1.0 : -1.0) * x.half_extents[k] * x.rotation.col(k);
      L.code |= (d > 0) << k;
    }
  }
  return true;
}
// The set of box x on its level L in the basis (u, w), counter-clockwise and settled, and if
// asked its feature in the numbering of polytope_from_box.
void level_patch(const Box& x, const BoxLevel& L, double tau, const Eigen::Vector3d& u, const Eigen::Vector3d& w,
                 Patch& P, ContactPatch::Feature* feature = nullptr);

// box_level_of, then level_patch, with the level's height along m.
bool box_level(const Box& x, const Eigen::Vector3d& m, double sign, double tau, const Eigen::Vector3d& u,
               const Eigen::Vector3d& w, Patch& P, double& height, ContactPatch::Feature* feature = nullptr);

// What box_pair_patch decided: the patch is in `out`; the boxes lie farther apart than the
// margin (the patch is empty, the distance unknown); or the axes do not decide it.
enum class BoxPatch { Done, Apart, Undecided };
// The contact patch of two valid boxes by their 15 separating axes (see patch.cpp).
BoxPatch box_pair_patch(const Box& a, const Box& b, double margin, ContactPatch& out);
// The contact patch of a valid box A and triangle B by their 13 separating axes (see patch.cpp).
BoxPatch box_triangle_patch(const Box& a, const Triangle& b, double margin, ContactPatch& out);

}  // namespace minksum::detail
