// Convex hulls of point sets (internal): the exact hull in 3D (quickhull on exact orientations,
// coplanar facets merged), and the planar hull the flat polytopes use.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace minksum::detail {

/// A hull's merged facets, flat: facet f has the outward unit normal normal[f] and the loop
/// index[start[f]] ... index[start[f + 1] - 1], point indices counter-clockwise from outside.
struct HullFacets {
  std::vector<Eigen::Vector3d> normal;
  std::vector<int> start, index;
  /// The number of facets.
  int count() const { return int(normal.size()); }
};

/// The sign of det[b - a; c - a; d - a], exactly: +1 where d lies on the side that
/// (b - a) x (c - a) points to, 0 where the four points are exactly coplanar (Shewchuk's filter,
/// then expansions; exact where every coordinate is 0 or within [2^-240, 1] in magnitude).
int orient3d(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d);

/// The exact convex hull of `points` (duplicates allowed): its facets, triangles merged where
/// exactly coplanar, each loop the facet's corners (extreme points only: no point inside an edge
/// or a facet) counter-clockwise from outside, with the loop's exact Newell normal, normalized.
/// Exact for the doubles given, but that components below 2^-240 (1e-72) of the largest one
/// read as zero. False where the points span no volume, are fewer than 4 or are not finite.
bool convex_hull(const std::vector<Eigen::Vector3d>& points, HullFacets& out);

/// The exact convex hull of the pairwise sums a[i] + b[j] (point i * |b| + j) as doubles, the
/// points a result's vertices are (as convex_hull gives it).
bool convex_hull_of_sums(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                         HullFacets& out);

/// Corners of the convex hull of the points `ids` projected along the largest axis of `normal`
/// (exactly: that coordinate dropped), counter-clockwise about `normal`, decided by exact
/// orientations: a point on the line through its neighbours, or a duplicate, is no corner. For
/// coplanar points it is their polygon's exact hull (components under 2^-240 of the largest
/// read as zero, as in convex_hull).
std::vector<int> planar_hull(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& ids,
                             const Eigen::Vector3d& normal);

}  // namespace minksum::detail
