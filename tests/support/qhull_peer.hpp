// Qhull as a peer of the hulls and the sums (libqhull_r, Debian's libqhull-dev): the benchmarks
// race it and the CLI's demo shows it; the library itself builds its hulls without it.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace minksum::peers {

/// One of Qhull's merged facets: its outward unit normal and its vertices' indices, ordered
/// counter-clockwise from outside.
struct QhullFacet {
  Eigen::Vector3d normal;
  std::vector<int> loop;
};

/// Qhull's hull of `points` (plain "qhull": coplanar facets merged to its tolerance), each
/// facet's loop ordered as the library's are; false where Qhull reports an error.
bool qhull_facets(const std::vector<Eigen::Vector3d>& points, std::vector<QhullFacet>& out);

}  // namespace minksum::peers
