// nanoflann 1.4's KDTreeSingleIndexAdaptor with L2_Simple_Adaptor over a vector of points.
#include "support/nanoflann_peer.hpp"

#include <nanoflann.hpp>

#include <limits>

namespace minksum::peers {

namespace {

struct Points {  // nanoflann's dataset interface, over the caller's cloud (not copied)
  const std::vector<Eigen::Vector3d>* pts = nullptr;
  size_t kdtree_get_point_count() const { return pts->size(); }
  double kdtree_get_pt(size_t i, size_t d) const { return (*pts)[i][int(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Points>, Points, 3>;

}  // namespace

struct NanoflannCloudPair::Impl {
  Points indexed, queries;  // the larger cloud, in the tree; the smaller one
  bool tree_on_a = true;
  std::unique_ptr<Tree> tree;
};

NanoflannCloudPair::NanoflannCloudPair(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b)
    : impl_(std::make_unique<Impl>()) {
  impl_->tree_on_a = a.size() >= b.size();
  impl_->indexed.pts = impl_->tree_on_a ? &a : &b;
  impl_->queries.pts = impl_->tree_on_a ? &b : &a;
  impl_->tree = std::make_unique<Tree>(3, impl_->indexed, nanoflann::KDTreeSingleIndexAdaptorParams(10));
  impl_->tree->buildIndex();
}

NanoflannCloudPair::~NanoflannCloudPair() = default;

double NanoflannCloudPair::distance(const Eigen::Isometry3d& pose, int* ia, int* ib) {
  // Queries in the indexed cloud's frame: B's points moved by the pose, or A's moved back.
  const Eigen::Matrix3d R = impl_->tree_on_a ? pose.linear() : Eigen::Matrix3d(pose.linear().transpose());
  const Eigen::Vector3d t = impl_->tree_on_a ? pose.translation() : Eigen::Vector3d(-(R * pose.translation()));
  double best2 = std::numeric_limits<double>::infinity();
  size_t best_indexed = 0, best_query = 0;
  const std::vector<Eigen::Vector3d>& queries = *impl_->queries.pts;
  for (size_t k = 0; k < queries.size(); ++k) {
    const Eigen::Vector3d q = R * queries[k] + t;
    size_t index = 0;
    double d2 = 0;
    nanoflann::KNNResultSet<double> result(1);
    result.init(&index, &d2);
    d2 = best2;  // the result set's worst distance: subtrees beyond the best so far are skipped
    impl_->tree->findNeighbors(result, q.data(), nanoflann::SearchParams());
    if (result.size() > 0 && d2 < best2) best2 = d2, best_indexed = index, best_query = k;
  }
  if (ia) *ia = int(impl_->tree_on_a ? best_indexed : best_query);
  if (ib) *ib = int(impl_->tree_on_a ? best_query : best_indexed);
  return std::sqrt(best2);
}

size_t NanoflannCloudPair::bytes() const { return impl_->tree->usedMemory(*impl_->tree); }

}  // namespace minksum::peers
