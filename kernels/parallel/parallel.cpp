// Batches over the cores (minksum/parallel.hpp): fixed blocks of kBatchBlock items, one task each,
// so that the answers do not depend on the number of threads. The caller and the threads of one
// pool, started on first use and asleep between batches, each take the next block from one
// atomic counter until none is left. oneTBB's pool was the first choice, but Debian's libtbb is
// not instrumented, so ThreadSanitizer cannot see its synchronization and reports every batch
// (ci/test runs the batches under it); a thread started per batch cost 50 us (this VM).

#include <minksum/parallel.hpp>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include <unistd.h>

namespace minksum {

namespace {

bool valid(const Poses& p, long n) { return p.data != nullptr && (p.count == 1 || p.count == n); }

// The first failure of a block, by index, and each item's status where the caller keeps them.
struct Failure {
  BatchStatus first;
  Status* each = nullptr;
  void note(Status s, long k) {
    if (each) each[k] = s;
    if (s != Status::Ok && first.status == Status::Ok) first = {s, k};
  }
};

// The process's batch threads: work(worker) runs on `helpers` of them (workers 1 to helpers)
// while the caller runs work(0). One batch at a time; a batch that finds the pool busy (another
// thread's batch) runs on its caller alone, with the same answers, and so does a batch in a
// child of fork(), which has none of the pool's threads (Python's multiprocessing forks).
// Never destroyed: its threads sleep until the process ends.
class Pool {
 public:
  static Pool& instance() {
    static Pool* const pool = new Pool;  // (reachable to the end: no exit-time teardown race)
    return *pool;
  }

  template <class Work>
  void run(int helpers, const Work& work) {
    if (getpid() != owner_) return work(0);  // a forked child: its mutexes may be held for good
    std::unique_lock<std::mutex> one(busy_, std::try_to_lock);
    if (!one || (helpers = grow(helpers)) == 0) return work(0);
    {
      std::lock_guard<std::mutex> lock(m_);
      job_ = &work, call_ = [](const void* job, int worker) { (*static_cast<const Work*>(job))(worker); };
      wanted_ = active_ = helpers, ++generation_;
    }
    wake_.notify_all();
    work(0);
    std::unique_lock<std::mutex> lock(m_);
    done_.wait(lock, [&] { return active_ == 0; });
  }

 private:
  // Starts threads up to `helpers` (as many as can be had); returns how many there are to use.
  int grow(int helpers) {
    try {
      while (int(threads_.size()) < helpers) threads_.emplace_back(&Pool::loop, this, int(threads_.size()) + 1);
    } catch (const std::system_error&) {
      // No more threads: the ones there are, and the caller, take every block.
    }
    return std::min(helpers, int(threads_.size()));
  }

  void loop(int worker) {
    long seen = 0;
    std::unique_lock<std::mutex> lock(m_);
    for (;;) {
      wake_.wait(lock, [&] { return generation_ != seen; });
      seen = generation_;
      if (worker > wanted_) continue;
      const void* job = job_;
      void (*call)(const void*, int) = call_;
      lock.unlock();
      call(job, worker);
      lock.lock();
      if (--active_ == 0) done_.notify_one();
    }
  }

  const pid_t owner_ = getpid();  // the process whose threads these are
  std::mutex busy_;                // one batch at a time
  std::mutex m_;     // guards the job below
  std::condition_variable wake_, done_;
  std::vector<std::thread> threads_;
  const void* job_ = nullptr;
  void (*call_)(const void*, int) = nullptr;
  long generation_ = 0;
  int wanted_ = 0, active_ = 0;
};

// Blocks of kUncachedBatchBlock: the 5,000 sums of the benchmark made 20 blocks of 256, and 2
// threads ran 1.58-1.78x one; 1.79-1.88x in blocks of 32. Blocks of 8 ran time of impact at 1.4x:
// the threads shared the counter's and the results' cache lines every few microseconds.

// Runs block(worker, begin, end) -> BatchStatus over the batch's blocks of `size` items on up to
// `workers` threads (the caller is worker 0), and returns the first failure by index. One vector
// per batch (not per item) keeps each block's failure; `worker` picks a thread's own scratch.
// Each worker runs its own copy of `block`, which holds its arguments by value: read through
// references, they sat in the caller's stack frame beside the locals the caller writes, and every
// item's read pulled that cache line across (2 threads ran 1.59x one; 1.89x with their own copies).
template <class Block>
BatchStatus run_blocks(long n, long size, int workers, const Block& block) {
  const long blocks = (n + size - 1) / size;
  const int helpers = int(std::min<long>(workers, blocks)) - 1;
  if (helpers <= 0) {  // the caller alone, in order: no vector
    BatchStatus first;
    for (long b = 0; b < blocks; ++b) {
      const BatchStatus f = block(0, b * size, std::min(n, (b + 1) * size));
      if (first.status == Status::Ok) first = f;
    }
    return first;
  }
  std::vector<BatchStatus> failures(static_cast<size_t>(blocks));
  alignas(64) std::atomic<long> next{0};  // its own cache line: the workers take blocks from it
  const auto work = [&](int worker) {
    const Block own = block;
    for (long b = next++; b < blocks; b = next++)
      failures[size_t(b)] = own(worker, b * size, std::min(n, (b + 1) * size));
  };
  Pool::instance().run(helpers, work);
  for (const BatchStatus& f : failures)
    if (f.status != Status::Ok) return f;
  return {};
}

constexpr BatchStatus kBadBatch{Status::InvalidArgument, -1};

// Items [begin, begin + count) of a batch's poses.
Poses part(Poses p, long begin, long count) { return p.count == 1 ? p : Poses{p.data + begin, count}; }

}  // namespace

BatchStatus proximity_batch(const ConvexShape& a, Poses poses_a, const ConvexShape& b, Poses poses_b, long n, Proximity* out,
                            Want want, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  return run_blocks(n, kBatchBlock, batch_threads(options),
                    [sa = &a, poses_a, sb = &b, poses_b, out, want, each = options.statuses](int, long begin, long end) {
    ProximityCache cache{};
    Failure f{{}, each};
    for (long k = begin; k < end; ++k) f.note(proximity(*sa, poses_a[k], *sb, poses_b[k], cache, out[k], want), k);
    return f.first;
  });
}

BatchStatus time_of_impact_batch(const ConvexShape& a, Poses a0, Poses a1, const ConvexShape& b, Poses b0, Poses b1, long n,
                                 TimeOfImpact* out, double tolerance, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(a0, n) || !valid(a1, n) || !valid(b0, n) || !valid(b1, n) || !out))) return kBadBatch;
  return run_blocks(n, kUncachedBatchBlock, batch_threads(options),
                    [sa = &a, a0, a1, sb = &b, b0, b1, out, tolerance, each = options.statuses](int, long begin, long end) {
    Failure f{{}, each};
    for (long k = begin; k < end; ++k) f.note(time_of_impact(*sa, a0[k], a1[k], *sb, b0[k], b1[k], out[k], tolerance), k);
    return f.first;
  });
}

BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const Octree& b, Poses poses_b, long n, MeshDistance* out,
                                MeshWorkspace& workspace, Status* statuses) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  return run_blocks(n, kBatchBlock, 1, [&](int, long begin, long end) {
    ProximityCache cache{};
    Failure f{{}, statuses};
    for (long k = begin; k < end; ++k) f.note(mesh_distance(a, poses_a[k], b, poses_b[k], workspace, cache, out[k]), k);
    return f.first;
  });
}

BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const Octree& b, Poses poses_b, long n, MeshDistance* out,
                                const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  // One workspace per thread, made before the threads start (not per item).
  const int workers = batch_threads(options);
  std::vector<MeshWorkspace> workspaces(size_t(std::min<long>(workers, (n + kBatchBlock - 1) / kBatchBlock)));
  for (MeshWorkspace& ws : workspaces) make_workspace(a, b, ws);
  return run_blocks(n, kBatchBlock, workers,
                    [ma = &a, poses_a, mb = &b, poses_b, out, ws = workspaces.data(), each = options.statuses](int worker, long begin, long end) {
    const long count = end - begin;
    BatchStatus s = mesh_distance_batch(*ma, part(poses_a, begin, count), *mb, part(poses_b, begin, count), count, out + begin,
                                        ws[worker], each ? each + begin : nullptr);
    if (s.status != Status::Ok) s.index += begin;
    return s;
  });
}

BatchStatus mesh_distance_batch(const Octree& a, Poses poses_a, const ConvexShape& shape, Poses poses_shape, long n,
                                MeshDistance* out, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!valid(poses_a, n) || !valid(poses_shape, n) || !out))) return kBadBatch;
  return run_blocks(n, kBatchBlock, batch_threads(options),
                    [ma = &a, poses_a, s = &shape, poses_shape, out, each = options.statuses](int, long begin, long end) {
    ProximityCache cache{};
    Failure f{{}, each};
    for (long k = begin; k < end; ++k) f.note(mesh_distance(*ma, poses_a[k], *s, poses_shape[k], cache, out[k]), k);
    return f.first;
  });
}

BatchStatus minkowski_sum_batch(const ConvexShape* a, Poses poses_a, const ConvexShape* b, Poses poses_b, long n,
                                MinkowskiSum* out, bool difference, SumParts parts, const BatchOptions& options) {
  if (n < 0 || (n > 0 && (!a || !b || !valid(poses_a, n) || !valid(poses_b, n) || !out))) return kBadBatch;
  using Sum = Status (*)(const ConvexShape&, const Eigen::Isometry3d&, const ConvexShape&, const Eigen::Isometry3d&,
                         MinkowskiSum&, SumParts);
  const Sum sum = difference ? Sum(&minkowski_difference) : Sum(&minkowski_sum);
  return run_blocks(n, kUncachedBatchBlock, batch_threads(options),
                    [a, poses_a, b, poses_b, out, sum, parts, each = options.statuses](int, long begin, long end) {
    Failure f{{}, each};
    for (long k = begin; k < end; ++k) f.note(sum(a[k], poses_a[k], b[k], poses_b[k], out[k], parts), k);
    return f.first;
  });
}

int batch_threads(const BatchOptions& options) {
  if (options.threads > 0) return options.threads;
  return std::max(1, int(std::thread::hardware_concurrency()));
}

BatchStatus run_batch(long n, long block, const BatchWork& work, const BatchOptions& options) {
  if (n < 0 || block < 1 || !work) return kBadBatch;
  // By reference: a worker's copy of a std::function could allocate (and throw) on a pool thread;
  // `work` is called once a block, so reading it where the caller keeps it costs nothing.
  return run_blocks(n, block, batch_threads(options), std::cref(work));
}

}  // namespace minksum
