// The Qhull peer (see qhull_peer.hpp): the bridge the library used before its exact hull.
#include "support/qhull_peer.hpp"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace minksum::peers {

namespace {

// Orders the points `ids` of a planar convex polygon counter-clockwise around `normal`.
void order_ccw(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal, std::vector<int>& ids) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k : ids) c += points[size_t(k)];
  c /= double(ids.size());
  // (u, w, normal) is right-handed, so increasing atan2 angle is counter-clockwise about normal.
  const Eigen::Vector3d u = normal.unitOrthogonal(), w = normal.cross(u);
  std::vector<std::pair<double, int>> keyed;
  for (int k : ids) {
    const Eigen::Vector3d d = points[size_t(k)] - c;
    keyed.emplace_back(std::atan2(d.dot(w), d.dot(u)), k);
  }
  std::sort(keyed.begin(), keyed.end());
  for (size_t k = 0; k < ids.size(); ++k) ids[k] = keyed[k].second;
}

}  // namespace

bool qhull_facets(const std::vector<Eigen::Vector3d>& points, std::vector<QhullFacet>& out) {
  out.clear();
  std::vector<coordT> coords(points.size() * 3);
  for (size_t k = 0; k < points.size(); ++k)
    for (int d = 0; d < 3; ++d) coords[3 * k + size_t(d)] = points[k][d];
  // Qhull's messages go to /dev/null, opened once per process (an open and close per call
  // would be part of every timing); stdio locks the stream, so threads may share it.
  static FILE* const devnull = std::fopen("/dev/null", "w");
  if (!devnull) return false;
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, devnull);
  // Plain "qhull" in 3-d merges coplanar facets by default ('C-0', 'Qx').
  char flags[] = "qhull";
  const int exitcode = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, flags, nullptr, devnull);
  if (!exitcode) {
    facetT* facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
      QhullFacet f;
      // Qhull's plane is normal . x + offset = 0 with an outward unit normal.
      f.normal = Eigen::Vector3d(facet->normal[0], facet->normal[1], facet->normal[2]);
      FOREACHvertex_(facet->vertices) f.loop.push_back(qh_pointid(qh, vertex->point));
      order_ccw(points, f.normal, f.loop);
      out.push_back(std::move(f));
    }
  }
  qh_freeqhull(qh, !qh_ALL);
  int curlong, totlong;
  qh_memfreeshort(qh, &curlong, &totlong);
  return exitcode == 0 && !out.empty();
}

}  // namespace minksum::peers
