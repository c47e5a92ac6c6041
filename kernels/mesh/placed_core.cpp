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
  core.shape = &p, core.vertices = int(p.vertices.size());
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
  // A face plane with every corner of t beyond it separates them: the widest such gap bounds the
  // distance from below, and is the distance where the corner nearest that plane lies over the
  // face (its foot is a point of the core that far away): a face resting over a surface.
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
    const Vector3d foot = t[corner] - gap * n[face];
    if (over_face(face, foot)) return on_t = t[corner], on_core = foot, gap;
  }
  for (const Vector3d& p : t)
    if (contains(p)) return on_t = on_core = p, 0.0;
  double best = std::numeric_limits<double>::infinity();
  TrianglePairs pairs;
  const auto found = [&](double d, const Vector3d& pc, const Vector3d& pt, int, int) {
    if (d < best) best = d, on_core = pc, on_t = pt;
  };
  // The nearest point of the core lies on a face whose normal points towards t's nearest point
  // (its normal cone), so no corner of t lies behind that face's plane only where all do: those
  // faces are skipped. (A corner on the plane counts: t in a flat core's plane.)
  for (int f = 0; f < faces; ++f)
    for (int k = first[f]; k < first[f + 1] && !(above[f] < 0); ++k)
      if (pairs.add(tri[k], t)) pairs.flush(found);
  pairs.flush(found);
  return best;
}

bool PlacedCore::over_face(int f, const Vector3d& p) const {
  const std::vector<int>& loop = shape->faces[size_t(f)].loop;
  for (size_t k = 0; k < loop.size(); ++k) {
    const Vector3d &a = v[loop[k]], &b = v[loop[(k + 1) % loop.size()]];
    if ((b - a).cross(p - a).dot(n[f]) < 0) return false;
  }
  return true;
}

}  // namespace minksum::detail
