// Convex hull of a 3D point set through Qhull, with coplanar facets merged (internal).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace minksum::detail {

/// One merged hull facet: outward unit normal and point indices counter-clockwise from outside.
struct HullFacet {
  Eigen::Vector3d normal;
  std::vector<int> loop;
};

/// Hull of `points` (not all coplanar). Returns false when Qhull reports an error.
bool qhull_facets(const std::vector<Eigen::Vector3d>& points, std::vector<HullFacet>& out);

/// Corners of the convex hull of the points `ids` projected onto the plane of `normal`,
/// counter-clockwise about it (Andrew's monotone chain). A point within eps (a distance) of the
/// line through its neighbours on the hull is not a corner, so collinear and duplicate points
/// are dropped.
std::vector<int> planar_hull(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
                             const Eigen::Vector3d& normal, double eps);

/// Orders the points `ids` of a planar convex polygon counter-clockwise around `normal`.
void order_ccw(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& normal, std::vector<int>& ids);

}  // namespace minksum::detail
