// A rounded shape's core placed in a mesh's frame (internal), as the mesh queries read it:
// mesh distance (shape_distance.cpp) and mesh contact (contact.cpp). A point, a segment, a
// flat polygon and a solid are one type: vertices, edges and faces, with the triangles and
// planes the exact distances need.
#pragma once

#include "mesh/mesh_internal.hpp"

#include <algorithm>
#include <limits>

namespace minksum::detail {

constexpr int kMaxCoreTriangles = 2 * kMaxToolVertices;  // a fan of all faces: 2V - 4

struct PlacedCore {
  const ConvexPolytope* shape = nullptr;  // the core in its own frame (edges' and faces' indices)
  Rigid pose;                             // where it is placed
  int vertices = 0, count = 0, faces = 0;
  bool solid = false;  // it has an inside (a point, a segment or a flat polygon has none)
  bool line = false;   // a point or a segment: `segment` holds its ends
  Eigen::Vector3d v[kMaxToolVertices];         // its vertices, placed
  Eigen::Vector3d tri[kMaxCoreTriangles][3];   // its surface as triangles (a point: (p, p, p); a segment: (p, q, q))
  int first[kMaxCoreTriangles + 1];            // face f's triangles: tri[first[f] .. first[f + 1])
  Eigen::Vector3d n[kMaxCoreTriangles];        // its faces' planes, n . x <= o inside
  double o[kMaxCoreTriangles];
  Eigen::Vector3d box_c, box_h, centre;        // its box, and a sphere about the box's centre
  double reach = 0;                            // the sphere's radius
  PlacedSegment segment;

  /// The core's point nearest x: exact for a point or a segment, else the sphere's centre.
  Eigen::Vector3d nearest(const Eigen::Vector3d& x) const { return line ? segment.nearest(x) : centre; }
  /// The core's highest value along unit u: exact for a point or a segment, else the sphere's.
  double support(const Eigen::Vector3d& u) const { return line ? segment.support(u) : u.dot(centre) + reach; }
  /// Whether point p lies inside the solid core (no plane has it beyond).
  bool contains(const Eigen::Vector3d& p) const {
    if (!solid) return false;
    for (int f = 0; f < faces; ++f)
      if (n[f].dot(p) > o[f]) return false;
    return true;
  }
  /// Triangle t before the exact kernel. Where its distance is proven without it, returns it
  /// and the pair: a corner inside a solid core, 0; a face plane with every corner beyond it
  /// and the nearest corner's foot on the face, that gap (a face resting over a surface); a gap
  /// past `beyond`, that lower bound, without the pair. Else returns -1 and calls add(k) for each
  /// core triangle k that can hold the nearest point: those of the faces that some corner of t
  /// does not lie behind (the nearest point's normal cone holds such a face), a line's one.
  template <class Add>
  double screen(const Eigen::Vector3d (&t)[3], Eigen::Vector3d& on_t, Eigen::Vector3d& on_core, double beyond,
                Add&& add) const {
    if (line) return add(0), -1.0;
    double gap = 0, above[kMaxCoreTriangles];
    int face = -1, corner = 0;
    for (int f = 0; f < faces; ++f) {
      const double h[3] = {n[f].dot(t[0]) - o[f], n[f].dot(t[1]) - o[f], n[f].dot(t[2]) - o[f]};
      const int k = h[0] <= h[1] ? (h[0] <= h[2] ? 0 : 2) : (h[1] <= h[2] ? 1 : 2);
      if (h[k] > gap) gap = h[k], face = f, corner = k;
      above[f] = std::max({h[0], h[1], h[2]});
    }
    if (face >= 0) {
      if (gap > beyond) return gap;
      const Eigen::Vector3d foot = t[corner] - gap * n[face];
      if (over_face(face, foot)) return on_t = t[corner], on_core = foot, gap;
    }
    for (const Eigen::Vector3d& p : t)
      if (contains(p)) return on_t = on_core = p, 0.0;
    for (int f = 0; f < faces; ++f)  // (a corner on the plane counts: t in a flat core's plane)
      for (int k = first[f]; k < first[f + 1] && !(above[f] < 0); ++k) add(k);
    return -1;
  }
  /// The exact distance of triangle t to the core and a nearest pair (0 with a shared point where
  /// they meet); past `beyond`, it may be any lower bound over it, without the pair.
  double distance(const Eigen::Vector3d (&t)[3], Eigen::Vector3d& on_t, Eigen::Vector3d& on_core,
                  double beyond = std::numeric_limits<double>::infinity()) const;
  /// Whether point p of face f's plane lies on the face (to the rounding of p's coordinates).
  bool over_face(int f, const Eigen::Vector3d& p) const;
};

/// The shape's core placed by `pose`; CapacityExceeded past kMaxToolVertices vertices.
Status place_core(const ConvexShape& shape, const Rigid& pose, PlacedCore& core);

}  // namespace minksum::detail
