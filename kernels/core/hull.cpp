// The Qhull bridge: the hull of a point set with coplanar facets merged (see hull.hpp).
#include "core/hull.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace minksum::detail {

void order_ccw(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal, std::vector<int>& ids) {
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int k : ids) c += points[k];
  c /= double(ids.size());
  // (u, w, normal) is right-handed, so increasing atan2 angle is counter-clockwise about normal.
  const Eigen::Vector3d u = normal.unitOrthogonal();
  const Eigen::Vector3d w = normal.cross(u);
  std::vector<std::pair<double, int>> keyed;
  keyed.reserve(ids.size());
  for (int k : ids) {
    const Eigen::Vector3d d = points[k] - c;
    keyed.emplace_back(std::atan2(d.dot(w), d.dot(u)), k);
  }
  std::sort(keyed.begin(), keyed.end());
  for (size_t k = 0; k < ids.size(); ++k) ids[k] = keyed[k].second;
}

std::vector<int> planar_hull(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
                             const Eigen::Vector3d& normal, double eps) {
  using Eigen::Vector2d;
  const Eigen::Vector3d u = normal.unitOrthogonal(), w = normal.cross(u);
  std::vector<std::pair<Vector2d, int>> q;
  for (int k : ids) q.push_back({Vector2d(points[k].dot(u), points[k].dot(w)), k});
  std::sort(q.begin(), q.end(), [](const auto& a, const auto& b) {
    return a.first.x() < b.first.x() || (a.first.x() == b.first.x() && a.first.y() < b.first.y());
  });
  q.erase(std::unique(q.begin(), q.end(), [](const auto& a, const auto& b) { return a.first == b.first; }), q.end());
  // a is dropped between o and b where it lies within eps of their line (or beyond it): a
  // distance, not an area, so that a far corner is kept beside two points nearly on top of
  // each other (their small triangle with it dropped it: a 1000-long triangle called collinear).
  auto flat = [eps](const Vector2d& o, const Vector2d& a, const Vector2d& b) {
    return (a - o).x() * (b - o).y() - (a - o).y() * (b - o).x() <= eps * (b - o).norm();
  };
  std::vector<std::pair<Vector2d, int>> h;
  for (int pass = 0; pass < 2; ++pass) {  // lower chain, then upper chain
    const size_t start = h.size();
    for (const auto& p : q) {
      while (h.size() >= start + 2 && flat(h[h.size() - 2].first, h.back().first, p.first)) h.pop_back();
      h.push_back(p);
    }
    h.pop_back();  // each chain's last point starts the other chain
    std::reverse(q.begin(), q.end());
  }
  std::vector<int> corners;
  for (const auto& p : h) corners.push_back(p.second);
  return corners;
}

bool qhull_facets(const std::vector<Eigen::Vector3d>& points, std::vector<HullFacet>& out) {
  out.clear();
  std::vector<coordT> coords(points.size() * 3);
  for (size_t k = 0; k < points.size(); ++k)
    for (int d = 0; d < 3; ++d) coords[3 * k + d] = points[k][d];

  // Qhull's messages go to /dev/null, opened once per process (an open and close per call was
  // part of every Method::Hull timing); stdio locks the stream, so threads may share it.
  static FILE* const devnull = std::fopen("/dev/null", "w");
  if (!devnull) return false;
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, devnull);
  // Plain "qhull" in 3-d merges coplanar facets by default ('C-0', 'Qx'), which is what we want.
  char flags[] = "qhull";
  const int exitcode = qh_new_qhull(qh, 3, int(points.size()), coords.data(), False, flags, nullptr, devnull);
  if (!exitcode) {
    facetT* facet;
    vertexT *vertex, **vertexp;
    FORALLfacets {
      HullFacet f;
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

}  // namespace minksum::detail
