// nanoflann (Debian's libnanoflann-dev), the kd-tree peer of the point-cloud distance: shared by
// the benchmarks and the tests (it is checked against brute force too).
#pragma once

#include <minksum/mesh.hpp>

#include <memory>
#include <vector>

namespace minksum::peers {

/// Two point clouds and a kd-tree over the larger one, built once.
class NanoflannCloudPair {
 public:
  /// Builds the kd-tree (leaf size 10, nanoflann's default) over the clouds, read in place (a
  /// copy would be timed as the peer's build): they must outlive the pair.
  NanoflannCloudPair(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b);
  ~NanoflannCloudPair();
  /// The closest pair of points, B placed by the pose in A's frame: one nearest-neighbour query
  /// per point of the smaller cloud, each bounded by the best distance so far (nanoflann prunes
  /// with it). Returns the distance; ia, ib name the points.
  double distance(const Eigen::Isometry3d& pose, int* ia = nullptr, int* ib = nullptr);
  /// Bytes of the kd-tree: nanoflann's node pool and index array (the points are the caller's).
  size_t bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace minksum::peers
