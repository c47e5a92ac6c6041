// minksum: many independent queries or sums in one call, split over the cores. Opt-in: the
// umbrella header does not include it, and it lives in its own library, minksum::parallel, so
// that a real-time user starts no threads. The batches share one pool of threads, started on
// the first batch and asleep between batches: give a batch thousands of items, not tens.
//
// A batch of queries that keep a cache (proximity, mesh distance) is cut into blocks of
// kBatchBlock items. Each block is one task: it runs its items in order with one cache, cold at
// the block's start (coherence along a trajectory), and one workspace per thread. The blocks are
// the same on any number of threads, so a batch's answers are bit for bit those of the single
// calls made in order with a cache cleared every kBatchBlock items, on 1 thread or on many. Time
// of impact and sums keep no cache: their answers are the single calls', in smaller blocks. Results go into caller-owned arrays; once a
// thread's workspace exists, no item allocates (a sum's result allocates only while it grows).
#pragma once

#include <minksum/mesh.hpp>
#include <minksum/query.hpp>
#include <minksum/sum.hpp>

#include <functional>

namespace minksum {

/// Items one task of a cached batch (proximity, mesh distance) runs in order from one cold cache.
constexpr long kBatchBlock = 256;

/// Items one task of a batch without a cache (time of impact, sums) runs: any cut gives the same
/// answers there, and small blocks even out the threads' last ones.
constexpr long kUncachedBatchBlock = 32;

/// n poses, or one pose for every item of the batch (count 1).
struct Poses {
  const Eigen::Isometry3d* data = nullptr;  ///< the poses
  long count = 0;                           ///< 1 (the same for every item) or the batch's size
  /// The pose of item k.
  const Eigen::Isometry3d& operator[](long k) const { return data[count == 1 ? 0 : k]; }
};

/// How a batch runs.
struct BatchOptions {
  int threads = 0;             ///< worker threads (0: one per core; 1: the calling thread alone)
  Status* statuses = nullptr;  ///< if not null, n entries: each item's own status
};

/// A batch's outcome: Ok, or the status of its first failed item (by index) and that index. A
/// failed item's result keeps its defaults; every other item is computed.
struct BatchStatus {
  Status status = Status::Ok;  ///< Ok, or the first failure's status
  long index = -1;             ///< that item (-1: none failed)
};

/// proximity(a, poses_a[k], b, poses_b[k], cache, out[k], want) for k < n. InvalidArgument (index
/// -1) for n < 0, a Poses whose count is neither 1 nor n, or null arrays with n > 0.
BatchStatus proximity_batch(const ConvexShape& a, Poses poses_a, const ConvexShape& b, Poses poses_b, long n, Proximity* out,
                            Want want = Want::Witnesses, const BatchOptions& options = {});

/// time_of_impact(a, a0[k], a1[k], b, b0[k], b1[k], out[k], tolerance) for k < n.
BatchStatus time_of_impact_batch(const ConvexShape& a, Poses a0, Poses a1, const ConvexShape& b, Poses b0, Poses b1, long n,
                                 TimeOfImpact* out, double tolerance = 0, const BatchOptions& options = {});

/// mesh_distance(a, poses_a[k], b, poses_b[k], workspace, cache, out[k]) for k < n, with one
/// workspace per thread.
BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const Octree& b, Poses poses_b, long n, MeshDistance* out,
                                const BatchOptions& options = {});

/// The same on the calling thread alone, with the caller's workspace (from make_workspace(a, b));
/// each item's status into `statuses` if not null.
BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const Octree& b, Poses poses_b, long n, MeshDistance* out,
                                MeshWorkspace& workspace, Status* statuses = nullptr);

/// mesh_distance(a, poses_a[k], shape, poses_shape[k], cache, out[k]) for k < n.
BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const ConvexShape& shape, Poses poses_shape, long n,
                                MeshDistance* out, const BatchOptions& options = {});

/// minkowski_sum (or, with `difference`, minkowski_difference) of a[k] under poses_a[k] and b[k]
/// under poses_b[k] into out[k], for k < n: N pairs of shapes. Reused results keep their capacity.
BatchStatus minkowski_sum_batch(const ConvexShape* a, Poses poses_a, const ConvexShape* b, Poses poses_b, long n,
                                MinkowskiSum* out, bool difference = false, SumParts parts = SumParts::Whole,
                                const BatchOptions& options = {});

/// A block of a batch: its items [begin, end) on thread `worker` (0, the caller, to threads - 1);
/// its first failure by index, or {}. It must not throw.
using BatchWork = std::function<BatchStatus(int worker, long begin, long end)>;

/// The threads a batch with these options runs on (workers 0 to this - 1).
int batch_threads(const BatchOptions& options);

/// Runs `work` over [0, n) in blocks of `block` items (>= 1), each once, on the batch threads,
/// the caller among them: the batches' own runner, for callers that convert their inputs and
/// results a block at a time (the Python module). The first failure by index.
BatchStatus run_batch(long n, long block, const BatchWork& work, const BatchOptions& options = {});

}  // namespace minksum
