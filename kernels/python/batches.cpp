// The batches of minksum/parallel.hpp from Python: poses as (N, 4, 4) arrays (or one pose for
// every item), results as arrays of N rows, and the work done without the GIL.

#include <minksum/parallel.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/stl.h>

#include <limits>

namespace minksum::python {

namespace {

// N poses in an (N, 4, 4) float64 array, read in place a block at a time, or one pose (anything
// pose_of takes) for every item. The last rows are checked here, with the GIL; rigidity is each
// item's to check (its status says). Float32 poses are projected onto the nearest rotation as
// pose_of's are, each as its block is read.
class PoseArray {
 public:
  PoseArray(const py::handle& value, const char* what) {
    const py::array raw = value.is_none() ? py::array() : py::array::ensure(value);
    if (!raw || raw.ndim() != 3) {
      one_ = pose_of(value, what);
      return;
    }
    single_ = single_precision(raw);
    array_ = Doubles::ensure(raw);
    if (!array_ || array_.shape(1) != 4 || array_.shape(2) != 4) refuse(what, "expected an (N, 4, 4) array of poses");
    size_ = long(array_.shape(0));
    const double* m = data_ = array_.data();
    for (long k = 0; k < size_; ++k, m += 16)
      if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
        refuse(what, "pose " + std::to_string(k) + ": the last row of a 4x4 pose must be (0, 0, 0, 1)");
  }
  /// 1 (one pose for every item) or N.
  long size() const { return size_; }
  /// The poses of items [begin, begin + count), converted into `buffer` (count poses) if need be.
  /// Needs no GIL.
  Poses block(long begin, long count, Eigen::Isometry3d* buffer) const {
    if (!array_) return {&one_, 1};
    const double* m = data_ + 16 * begin;
    for (long k = 0; k < count; ++k, m += 16) {
      buffer[k].matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
      if (single_) buffer[k].linear() = float32_rotation(buffer[k].linear());
    }
    return {buffer, count};
  }

 private:
  Doubles array_{py::reinterpret_steal<Doubles>(py::handle())};
  const double* data_ = nullptr;  // array_'s
  Eigen::Isometry3d one_ = Eigen::Isometry3d::Identity();
  long size_ = 1;
  bool single_ = false;  // given in float32
};

// The batch's size: every array of poses has it (0 included), or one pose.
long batch_size(std::initializer_list<const PoseArray*> arrays) {
  long n = -1;
  for (const PoseArray* a : arrays)
    if (a->size() != 1 && n >= 0 && a->size() != n) refuse("poses", "every array of poses must hold one pose or the same N");
    else if (a->size() != 1) n = a->size();
  return n < 0 ? 1 : n;
}

// A batch refused whole (its arguments, not an item: the module's own error if it happens).
void check_batch(const BatchStatus& s, const char* what) {
  if (s.status != Status::Ok && s.index < 0) check(s.status, what);
}

// A batch thread's scratch for a block's poses, results and statuses.
struct Scratch {
  std::vector<Eigen::Isometry3d> poses[4];
  std::vector<Proximity> proximity;
  std::vector<TimeOfImpact> impact;
  std::vector<MeshDistance> distance;
  std::vector<Status> status;
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

template <class T>
T* sized(std::vector<T>& v, long n) {
  if (long(v.size()) < n) v.resize(size_t(n));
  return v.data();
}

// The result's column `name`: `out`'s array (a result of the same function and N, refilled in
// place), or a new (N,) or (N, width) array. Its data.
template <class T>
T* column(py::dict& fields, const py::handle& out, const char* name, long n, int width = 1) {
  if (out.is_none()) {
    py::array_t<T> a = width == 1 ? py::array_t<T>(n) : py::array_t<T>({py::ssize_t(n), py::ssize_t(width)});
    fields[name] = a;
    return a.mutable_data();
  }
  const py::object given = py::getattr(out, name, py::none());
  const bool fits = py::array_t<T, py::array::c_style>::check_(given) &&
                    py::reinterpret_borrow<py::array>(given).ndim() == (width == 1 ? 1 : 2) &&
                    py::reinterpret_borrow<py::array>(given).shape(0) == n &&
                    (width == 1 || py::reinterpret_borrow<py::array>(given).shape(1) == width);
  if (!fits) refuse("out", std::string("its ") + name + " is not the array a batch of " + std::to_string(n) + " items returns");
  fields[name] = given;
  return static_cast<T*>(py::reinterpret_borrow<py::array>(given).mutable_data());
}

void put(double* column, long k, const Eigen::Vector3d& v) { std::copy(v.data(), v.data() + 3, column + 3 * k); }

// The scratch of each of `workers` batch threads, sized for blocks of `block` items with their
// results in `results`. Sized here, on the calling thread with the GIL (the batch threads
// allocate nothing: an exception there would end the process; here it is Python's MemoryError),
// and kept by the calling thread from one batch to the next (a block's worth per thread, some
// hundred kB): a loop of batches touches no new memory, where a fresh page can cost microseconds
// (in a VM, often).
template <class T>
Scratch* scratch_for(int workers, long block, std::vector<T> Scratch::*results) {
  thread_local std::vector<Scratch> scratch;
  if (scratch.size() < size_t(workers)) scratch.resize(size_t(workers));
  for (Scratch& s : scratch) {
    sized(s.*results, block), sized(s.status, block);
    for (std::vector<Eigen::Isometry3d>& p : s.poses) sized(p, block);
  }
  return scratch.data();
}

// Runs run(worker's scratch, worker, begin, count, results, options) -> BatchStatus on the
// batch's blocks of `block` items over the batch threads, without the GIL, each block's results
// and statuses into its thread's scratch, then store(k, result, status) for the block's items: the poses are converted and the
// results stored by the threads, each its own blocks (done a chunk at a time on the caller, they
// left 2 threads at 1.3-1.7x one). The first failure by index. `store` holds its columns by
// value, and each thread runs its own copy: read through references, they would sit in the
// caller's stack frame, whose cache line the other thread would pull across on every item (as
// parallel.cpp's comment tells).
template <class T, class Run, class Store>
BatchStatus blocked(long n, long block, int threads, std::vector<T> Scratch::*results, const Run& run, const Store& store) {
  Scratch* const scratch = scratch_for(batch_threads({threads}), block, results);
  py::gil_scoped_release unlocked;
  return run_batch(
      n, block,
      [run, store, results, scratch](int worker, long begin, long end) {
        const long count = end - begin;
        Scratch& mine = scratch[worker];
        T* r = (mine.*results).data();
        Status* each = mine.status.data();
        BatchStatus s = run(mine, worker, begin, count, r, BatchOptions{1, each});
        for (long k = 0; k < count; ++k) store(begin + k, r[k], each[k]);
        if (s.status != Status::Ok && s.index >= 0) s.index += begin;
        return s;
      },
      {threads});
}

// The poses of a block, converted into the i-th pose scratch of the block's thread.
Poses block_of(const PoseArray& p, Scratch& scratch, int i, long begin, long count) {
  return p.block(begin, count, scratch.poses[i].data());
}

py::object result(py::dict& fields, const py::handle& out) {
  if (!out.is_none()) return py::reinterpret_borrow<py::object>(out);
  return py::module_::import("types").attr("SimpleNamespace")(**fields);
}

py::object proximities(const ConvexShape& a, const py::handle& pose_a, const ConvexShape& b, const py::handle& pose_b, Want want,
                       int threads, const py::handle& out) {
  const PoseArray pa(pose_a, "poses_a"), pb(pose_b, "poses_b");
  const long n = batch_size({&pa, &pb});
  const Want w = want_of(want);
  py::dict f;
  bool* intersecting = column<bool>(f, out, "intersecting", n);
  double* distance = column<double>(f, out, "distance", n);
  double* point_a = column<double>(f, out, "point_a", n, 3);
  double* point_b = column<double>(f, out, "point_b", n, 3);
  double* depth = column<double>(f, out, "penetration_depth", n);
  double* direction = column<double>(f, out, "penetration_direction", n, 3);
  double* max_distance = column<double>(f, out, "max_distance", n);
  int* status = column<int>(f, out, "status", n);
  const BatchStatus s = blocked(
      n, kBatchBlock, threads, &Scratch::proximity,
      [&](Scratch& mine, int, long begin, long count, Proximity* r, const BatchOptions& o) {
        return proximity_batch(a, block_of(pa, mine, 0, begin, count), b, block_of(pb, mine, 1, begin, count), count, r, w, o);
      },
      [=](long k, Proximity p, Status st) {
        if (st == Status::Ok) not_asked(w, p);
        else not_asked(Want(0), p);  // (a failed item: nothing was computed)
        intersecting[k] = p.intersecting, distance[k] = p.distance, depth[k] = p.penetration_depth;
        max_distance[k] = p.max_distance, status[k] = int(st);
        put(point_a, k, p.point_a), put(point_b, k, p.point_b), put(direction, k, p.penetration_direction);
      });
  check_batch(s, "proximity_batch");
  return result(f, out);
}

py::object impacts(const ConvexShape& a, const py::handle& a0, const py::handle& a1, const ConvexShape& b, const py::handle& b0,
                   const py::handle& b1, double tolerance, int threads, const py::handle& out) {
  const PoseArray p0(a0, "a0"), p1(a1, "a1"), q0(b0, "b0"), q1(b1, "b1");
  const long n = batch_size({&p0, &p1, &q0, &q1});
  py::dict f;
  bool* hit = column<bool>(f, out, "hit", n);
  double* time = column<double>(f, out, "time", n);
  double* distance = column<double>(f, out, "distance", n);
  double* normal = column<double>(f, out, "normal", n, 3);
  double* point_a = column<double>(f, out, "point_a", n, 3);
  double* point_b = column<double>(f, out, "point_b", n, 3);
  int* status = column<int>(f, out, "status", n);
  const BatchStatus s = blocked(
      n, kUncachedBatchBlock, threads, &Scratch::impact,
      [&](Scratch& mine, int, long begin, long count, TimeOfImpact* r, const BatchOptions& o) {
        return time_of_impact_batch(a, block_of(p0, mine, 0, begin, count), block_of(p1, mine, 1, begin, count), b, block_of(q0, mine, 2, begin, count),
                                    block_of(q1, mine, 3, begin, count), count, r, tolerance, o);
      },
      [=](long k, const TimeOfImpact& t, Status st) {
        const bool ok = st == Status::Ok;  // (a failed item: NaN, no hit)
        hit[k] = ok && t.hit, time[k] = ok ? t.time : kNaN, distance[k] = ok ? t.distance : kNaN, status[k] = int(st);
        const Eigen::Vector3d none = Eigen::Vector3d::Constant(kNaN);
        put(normal, k, ok ? t.normal : none), put(point_a, k, ok ? t.point_a : none), put(point_b, k, ok ? t.point_b : none);
      });
  check_batch(s, "time_of_impact_batch");
  return result(f, out);
}

template <class Other>
py::object mesh_distances(const Octree& a, const py::handle& pose_a, const Other& b, const py::handle& pose_b, int threads,
                          const py::handle& out) {
  const PoseArray pa(pose_a, "poses_a"), pb(pose_b, "poses_b");
  const long n = batch_size({&pa, &pb});
  py::dict f;
  double* distance = column<double>(f, out, "distance", n);
  double* point_a = column<double>(f, out, "point_a", n, 3);
  double* point_b = column<double>(f, out, "point_b", n, 3);
  int* triangle_a = column<int>(f, out, "triangle_a", n);
  int* triangle_b = column<int>(f, out, "triangle_b", n);
  bool* intersecting = column<bool>(f, out, "intersecting", n);
  int* status = column<int>(f, out, "status", n);
  // One workspace per thread for two meshes, made before the threads start (none for a shape).
  std::vector<MeshWorkspace> workspaces;
  if constexpr (std::is_same_v<Other, Octree>) {
    workspaces.resize(size_t(batch_threads({threads})));
    for (MeshWorkspace& ws : workspaces) make_workspace(a, b, ws);
  }
  const BatchStatus s = blocked(
      n, kBatchBlock, threads, &Scratch::distance,
      [&](Scratch& mine, int worker, long begin, long count, MeshDistance* r, const BatchOptions& o) {
        const Poses ka = block_of(pa, mine, 0, begin, count), kb = block_of(pb, mine, 1, begin, count);
        if constexpr (std::is_same_v<Other, Octree>)
          return mesh_distance_batch(a, ka, b, kb, count, r, workspaces[size_t(worker)], o.statuses);
        else
          return mesh_distance_batch(a, ka, b, kb, count, r, o);
      },
      [=](long k, const MeshDistance& d, Status st) {
        const bool ok = st == Status::Ok;  // (a failed item: NaN, no triangles)
        distance[k] = ok ? d.distance : kNaN, triangle_a[k] = ok ? d.triangle_a : -1, triangle_b[k] = ok ? d.triangle_b : -1;
        intersecting[k] = ok && d.intersecting, status[k] = int(st);
        const Eigen::Vector3d none = Eigen::Vector3d::Constant(kNaN);
        put(point_a, k, ok ? d.point_a : none), put(point_b, k, ok ? d.point_b : none);
      });
  check_batch(s, "mesh_distance_batch");
  return result(f, out);
}

// The sums of N pairs as a minksum.SumList (a list of Sum, failed items empty) with each item's status.
py::object sums(const std::vector<ConvexShape>& a, const py::handle& pose_a, const std::vector<ConvexShape>& b,
                const py::handle& pose_b, bool difference, SumParts parts, int threads) {
  if (a.size() != b.size()) refuse("b", "expected as many shapes as a");
  const PoseArray pa(pose_a, "poses_a"), pb(pose_b, "poses_b");
  const long n = long(a.size());
  if ((pa.size() != 1 && pa.size() != n) || (pb.size() != 1 && pb.size() != n))
    refuse("poses", "every array of poses must hold one pose or one per pair");
  std::vector<Eigen::Isometry3d> ba(size_t(pa.size() == 1 ? 0 : n)), bb(size_t(pb.size() == 1 ? 0 : n));
  std::vector<MinkowskiSum> out(static_cast<size_t>(n));
  py::array_t<int> status(n);
  std::vector<Status> each(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = minkowski_sum_batch(a.data(), pa.block(0, n, ba.data()), b.data(), pb.block(0, n, bb.data()), n, out.data(), difference, parts,
                            {threads, each.data()});
  }
  check_batch(s, difference ? "minkowski_difference_batch" : "minkowski_sum_batch");
  for (long k = 0; k < n; ++k) status.mutable_data()[k] = int(each[size_t(k)]);
  py::object list = py::module_::import("minksum").attr("SumList")(py::cast(std::move(out)));
  list.attr("status") = status;
  return list;
}

}  // namespace

void register_batches(py::module_& m) {
  const char* const threads_doc =
      "Every item is answered: `status` holds each one's Status code (0: OK; minksum.Status(code) names it), and a\n"
      "failed item's numbers are NaN. N may be 0. threads: 0 one per core, 1 the calling thread alone. out: a result of\n"
      "an earlier call with the same N, refilled in place and returned (a loop of batches then allocates nothing).\n"
      "Runs without the GIL.";
  m.def("proximity_batch", &proximities, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("want") = Want::Witnesses, py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("proximity of a and b under N poses each ((N, 4, 4) arrays, or one pose for all): a namespace of\n"
                     "arrays (intersecting, distance, point_a, point_b, penetration_depth, penetration_direction, max_distance,\n"
                     "status), N rows each; the columns `want` did not ask for are NaN. Blocks of 256 poses run in order from\n"
                     "one cache: the same answers on any number of threads.\n") +
         threads_doc)
            .c_str());
  m.def("time_of_impact_batch", &impacts, py::arg("a"), py::arg("a0"), py::arg("a1"), py::arg("b"), py::arg("b0"), py::arg("b1"),
        py::arg("tolerance") = 0.0, py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("time_of_impact of N motions: arrays hit, time, distance, normal, point_a, point_b, status.\n") +
         threads_doc)
            .c_str());
  m.def("mesh_distance_batch", &mesh_distances<Octree>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("mesh_distance under N poses: arrays distance, point_a, point_b, triangle_a, triangle_b,\n"
                     "intersecting, status; one workspace per thread.\n") +
         threads_doc)
            .c_str());
  m.def("mesh_distance_batch", &mesh_distances<ConvexShape>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0, py::arg("out") = py::none(), "mesh_distance of a mesh and a convex shape under N poses.");
  m.def(
      "minkowski_sum_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, false, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      "The sums of N pairs: shapes a[k] and b[k] under poses_a[k] and poses_b[k]; a SumList (a list of Sum, a failed\n"
      "pair's empty) whose `status` holds each pair's Status code. threads: 0 one per core, 1 the calling thread alone.\n"
      "Runs without the GIL.");
  m.def(
      "minkowski_difference_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, true, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      "The differences of N pairs; a SumList as minkowski_sum_batch's.");
}

}  // namespace minksum::python
