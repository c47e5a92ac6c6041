// Batches over the cores (minksum/parallel.hpp): fixed blocks of kBatchBlock items, one task each,
// so that the answers do not depend on the number of threads. The threads are std::threads
// started per batch, each taking the next block from one atomic counter until none is left:
// oneTBB's pool was the first choice, but Debian's libtbb is not instrumented, so
// ThreadSanitizer cannot see its synchronization and reports every batch (ci/test runs the
// batches under it).

#include <minksum/parallel.hpp>

#include <algorithm>
#include <atomic>
#include <system_error>
#include <thread>
#include <vector>

namespace minksum {

namespace {

bool valid(const Poses& p, long n) { return p.data != nullptr && (p.count == 1 || p.count == n); }

// The first failure of a block, by index.
struct Failure {
  BatchStatus first;
  void note(Status s, long k) {
    if (s != Status::Ok && first.status == Status::Ok) first = {s, k};
  }
};

// Runs block(worker, begin, end) -> BatchStatus over the batch's blocks on up to
// `options.threads` threads (the caller is worker 0), and returns the first failure by index.
// One vector per batch (not per item) keeps each block's failure, so no thread writes where
// another does; `worker` picks a thread's own scratch.
template <class Block>
BatchStatus run_blocks(long n, int workers, const Block& block) {
  const long blocks = (n + kBatchBlock - 1) / kBatchBlock;
  std::vector<BatchStatus> failures(size_t(std::max(blocks, 0L)));
  std::atomic<long> next{0};
  const auto work = [&](int worker) {
    for (long b = next++; b < blocks; b = next++)
      failures[size_t(b)] = block(worker, b * kBatchBlock, std::min(n, (b + 1) * kBatchBlock));
  };
  std::vector<std::thread> helpers;
  try {
    for (int w = 1; w < std::min<long>(workers, blocks); ++w) helpers.emplace_back(work, w);
  } catch (const std::system_error&) {
    // No more threads to be had: the ones started, and the caller, take every block.
  }
  work(0);
  for (std::thread& t : helpers) t.join();
  for (const BatchStatus& f : failures)
    if (f.status != Status::Ok) return f;
  return {};
}

// The threads a batch runs on: one per core by default.
int workers_of(const BatchOptions& options) {
  if (options.threads > 0) return options.threads;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

constexpr BatchStatus kBadBatch{Status::InvalidArgument, -1};


}  // namespace

BatchStatus proximity_batch(const ConvexShape& a, Poses poses_a, const ConvexShape& b, Poses poses_b, long n, Proximity* out,
                            Want want, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  return run_blocks(n, workers_of(options), [&](int, long begin, long end) {
    ProximityCache cache{};
    Failure f;
    for (long k = begin; k < end; ++k) f.note(proximity(a, poses_a[k], b, poses_b[k], cache, out[k], want), k);
    return f.first;
  });
}

BatchStatus time_of_impact_batch(const ConvexShape& a, Poses a0, Poses a1, const ConvexShape& b, Poses b0, Poses b1, long n,
                                 TimeOfImpact* out, double tolerance, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(a0, n) || !valid(a1, n) || !valid(b0, n) || !valid(b1, n) || !out))) return kBadBatch;
  return run_blocks(n, workers_of(options), [&](int, long begin, long end) {
    Failure f;
    for (long k = begin; k < end; ++k) f.note(time_of_impact(a, a0[k], a1[k], b, b0[k], b1[k], out[k], tolerance), k);
    return f.first;
  });
}

BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const Octree& b, Poses poses_b, long n, MeshDistance* out,
                                const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  // One workspace per thread, made before the threads start (not per item).
  const int workers = workers_of(options);
  std::vector<MeshWorkspace> workspaces(size_t(std::min<long>(workers, (n + kBatchBlock - 1) / kBatchBlock)));
  for (MeshWorkspace& ws : workspaces) make_workspace(a, b, ws);
  return run_blocks(n, workers, [&](int worker, long begin, long end) {
    MeshWorkspace& ws = workspaces[size_t(worker)];
    ProximityCache cache{};
    Failure f;
    for (long k = begin; k < end; ++k) f.note(mesh_distance(a, poses_a[k], b, poses_b[k], ws, cache, out[k]), k);
    return f.first;
  });
}

BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const ConvexShape& shape, Poses poses_shape, long n,
                                MeshDistance* out, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_shape, n) || !out))) return kBadBatch;
  return run_blocks(n, workers_of(options), [&](int, long begin, long end) {
    ProximityCache cache{};
    Failure f;
    for (long k = begin; k < end; ++k) f.note(mesh_distance(a, poses_a[k], shape, poses_shape[k], cache, out[k]), k);
    return f.first;
  });
}

BatchStatus minkowski_sum_batch(const ConvexShape* a, Poses poses_a, const ConvexShape* b, Poses poses_b, long n,
                                MinkowskiSum* out, bool difference, SumParts parts, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!a || !b || !valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  using Sum = Status (*)(const ConvexShape&, const Eigen::Isometry3d&, const ConvexShape&, const Eigen::Isometry3d&,
                         MinkowskiSum&, SumParts);
  const Sum sum = difference ? Sum(&minkowski_difference) : Sum(&minkowski_sum);
  return run_blocks(n, workers_of(options), [&](int, long begin, long end) {
    Failure f;
    for (long k = begin; k < end; ++k) f.note(sum(a[k], poses_a[k], b[k], poses_b[k], out[k], parts), k);
    return f.first;
  });
}

}  // namespace minksum
