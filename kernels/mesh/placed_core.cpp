// A rounded shape's core placed in a mesh's frame, and a triangle's exact distance to it.
#include "mesh/placed_core.hpp"

#include "query/triangle_pairs.hpp"
#include "shape/shape_data.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace minksum::detail {

using Eigen::Vector3d;

Status place_core(const ConvexShape& shape, const Rigid& pose, PlacedCore& core) {
  const ConvexPolytope& p = shape.polytope();
  if (p.vertices.size() > size_t(kMaxToolVertices)) return Status::CapacityExceeded;
  core.shape = &p, core.pose = pose, core.vertices = int(p.vertices.size());
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int k = 0; k < core.vertices; ++k) {
    core.v[k] = pose.point(p.vertices[size_t(k)]);
    lo = lo.cwiseMin(core.v[k]), hi = hi.cwiseMax(core.v[k]);
  }
  core.box_c = (lo + hi) / 2, core.box_h = (hi - lo) / 2, core.centre = core.box_c;
  for (int k = 0; k < core.vertices; ++k) core.reach = std::max(core.reach, (core.v[k] - core.centre).norm());
  if (!ShapeAccess::data(shape)->has_faces()) {  // a point or a segment
    const Vector3d s0 = core.v[0], s1 = core.v[core.vertices - 1];
    core.tri[0][0] = s0, core.tri[0][1] = s1, core.tri[0][2] = s1;
    core.count = 1, core.line = true, core.segment = {s0, s1};
    return Status::Ok;
  }
  core.solid = !p.flat;
  for (const Face& f : p.faces) {
    core.first[core.faces] = core.count;
    for (size_t k = 1; k + 1 < f.loop.size(); ++k) {
      const Vector3d c[3] = {core.v[f.loop[0]], core.v[f.loop[k]], core.v[f.loop[k + 1]]};
      std::copy(c, c + 3, core.tri[core.count++]);
    }
    pose.plane(f.normal, f.offset, core.n[core.faces], core.o[core.faces]);
    core.first[++core.faces] = core.count;
  }
  return Status::Ok;
}

double PlacedCore::distance(const Vector3d (&t)[3], Vector3d& on_t, Vector3d& on_core, double beyond) const {
  if (line) return minksum::triangle_distance(t, tri[0], on_t, on_core);
  double best = std::numeric_limits<double>::infinity();
  TrianglePairs pairs;
  const auto found = [&](double d, const Vector3d& pc, const Vector3d& pt, int, int) {
    if (d < best) best = d, on_core = pc, on_t = pt;
  };
  const auto add = [&](int k) {
    if (pairs.add(tri[k], t)) pairs.flush(found);
  };
  if (const double d = screen(t, on_t, on_core, beyond, add); d >= 0) return d;
  pairs.flush(found);
  return best;
}

// In the body frame, where the face is as given: placed far from the origin, its corners round
// by eps |t| each, and past its size they collapse to one point, over which every point "lies"
// (a cube at 1e57 took 1e55 for the distance 1e57). p brought back errs by eps |p| alone.
bool PlacedCore::over_face(int f, const Vector3d& p) const {
  const Face& face = shape->faces[size_t(f)];
  const Vector3d x = pose.body_point(p);
  for (size_t k = 0; k < face.loop.size(); ++k) {
    const Vector3d &a = shape->vertices[size_t(face.loop[k])],
                   &b = shape->vertices[size_t(face.loop[(k + 1) % face.loop.size()])];
    if ((b - a).cross(x - a).dot(face.normal) < 0) return false;
  }
  return true;
}

}  // namespace minksum::detail
