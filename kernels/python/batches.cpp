// The batches of minksum/parallel.hpp from Python: poses as (N, 4, 4) arrays (or one pose for
// every item), results as arrays of N rows, and the work done without the GIL.

#include <minksum/parallel.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/stl.h>

namespace minksum::python {

namespace {

// N poses in an (N, 4, 4) float64 array, read in place a chunk at a time, or one pose (anything
// pose_of takes) for every item. The last rows are checked here, with the GIL; rigidity is each
// item's to check (the batch reports the first item that fails).
class PoseArray {
 public:
  PoseArray(const py::handle& value, const char* what) {
    const py::array raw = value.is_none() ? py::array() : py::array::ensure(value);
    if (!raw || raw.ndim() != 3) {
      one_ = pose_of(value, what);
      return;
    }
    array_ = Doubles::ensure(raw);
    if (!array_ || array_.shape(1) != 4 || array_.shape(2) != 4) refuse(what, "expected an (N, 4, 4) array of poses");
    size_ = long(array_.shape(0));
    const double* m = array_.data();
    for (long k = 0; k < size_; ++k, m += 16)
      if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1)
        refuse(what, "pose " + std::to_string(k) + ": the last row of a 4x4 pose must be (0, 0, 0, 1)");
  }
  /// 1 (one pose for every item) or N.
  long size() const { return size_; }
  /// The poses of items [begin, begin + count), converted into `buffer` (count poses) if need be.
  Poses chunk(long begin, long count, Eigen::Isometry3d* buffer) const {
    if (!array_) return {&one_, 1};
    const double* m = array_.data() + 16 * begin;
    for (long k = 0; k < count; ++k, m += 16) buffer[k].matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
    return {buffer, count};
  }

 private:
  Doubles array_{py::reinterpret_steal<Doubles>(py::handle())};
  Eigen::Isometry3d one_ = Eigen::Isometry3d::Identity();
  long size_ = 1;
};

// The batch's size: every array of poses has it, or one pose.
long batch_size(std::initializer_list<const PoseArray*> arrays) {
  long n = 1;
  for (const PoseArray* a : arrays) n = std::max(n, a->size());
  for (const PoseArray* a : arrays)
    if (a->size() != 1 && a->size() != n) refuse("poses", "every array of poses must hold one pose or the same N");
  return n;
}

void check_batch(const BatchStatus& s, const char* what) {
  if (s.status == Status::Ok) return;
  check(s.status, (std::string(what) + ": item " + std::to_string(s.index)).c_str());
}

// Items per chunk: the batch runs a chunk at a time into scratch that stays in cache, and each
// chunk is copied into the result's columns. A multiple of kBatchBlock, so that the blocks, and
// the answers, are the whole batch's.
constexpr long kChunk = 16 * kBatchBlock;

// A calling thread's scratch, kept from one batch to the next (at most about 3 MB): a loop of
// batches touches no new memory, where a fresh page can cost microseconds (in a VM, often).
struct Scratch {
  std::vector<Eigen::Isometry3d> poses[4];
  std::vector<Proximity> proximity;
  std::vector<TimeOfImpact> impact;
  std::vector<MeshDistance> distance;
};

Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

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

// Runs run(begin, count, results) -> BatchStatus chunk by chunk into `results` (the thread's
// scratch), then store(k, result) for each item, without the GIL; stops at the first chunk with
// a failure (its index is the batch's first).
template <class T, class Run, class Store>
BatchStatus chunked(long n, std::vector<T>& results, const Run& run, const Store& store) {
  py::gil_scoped_release unlocked;
  T* r = sized(results, std::min(n, kChunk));
  for (long begin = 0; begin < n; begin += kChunk) {
    const long count = std::min(kChunk, n - begin);
    const BatchStatus s = run(begin, count, r);
    if (s.status != Status::Ok) return {s.status, begin + s.index};
    for (long k = 0; k < count; ++k) store(begin + k, r[k]);
  }
  return {};
}

// The poses of a chunk, the i-th array's converted into the thread's i-th pose scratch.
Poses chunk_of(const PoseArray& p, int i, long begin, long count) {
  return p.chunk(begin, count, sized(scratch().poses[i], count));
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
  const BatchStatus s = chunked(
      n, scratch().proximity,
      [&](long begin, long count, Proximity* r) {
        return proximity_batch(a, chunk_of(pa, 0, begin, count), b, chunk_of(pb, 1, begin, count), count, r, w, {threads});
      },
      [&](long k, const Proximity& p) {
        intersecting[k] = p.intersecting, distance[k] = p.distance, depth[k] = p.penetration_depth;
        max_distance[k] = p.max_distance;
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
  const BatchStatus s = chunked(
      n, scratch().impact,
      [&](long begin, long count, TimeOfImpact* r) {
        return time_of_impact_batch(a, chunk_of(p0, 0, begin, count), chunk_of(p1, 1, begin, count), b, chunk_of(q0, 2, begin, count),
                                    chunk_of(q1, 3, begin, count), count, r, tolerance, {threads});
      },
      [&](long k, const TimeOfImpact& t) {
        hit[k] = t.hit, time[k] = t.time, distance[k] = t.distance;
        put(normal, k, t.normal), put(point_a, k, t.point_a), put(point_b, k, t.point_b);
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
  const BatchStatus s = chunked(
      n, scratch().distance,
      [&](long begin, long count, MeshDistance* r) {
        return mesh_distance_batch(a, chunk_of(pa, 0, begin, count), b, chunk_of(pb, 1, begin, count), count, r, {threads});
      },
      [&](long k, const MeshDistance& d) {
        distance[k] = d.distance, triangle_a[k] = d.triangle_a, triangle_b[k] = d.triangle_b, intersecting[k] = d.intersecting;
        put(point_a, k, d.point_a), put(point_b, k, d.point_b);
      });
  check_batch(s, "mesh_distance_batch");
  return result(f, out);
}

std::vector<MinkowskiSum> sums(const std::vector<ConvexShape>& a, const py::handle& pose_a, const std::vector<ConvexShape>& b,
                               const py::handle& pose_b, bool difference, SumParts parts, int threads) {
  if (a.size() != b.size()) refuse("b", "expected as many shapes as a");
  const PoseArray pa(pose_a, "poses_a"), pb(pose_b, "poses_b");
  const long n = long(a.size());
  if ((pa.size() != 1 && pa.size() != n) || (pb.size() != 1 && pb.size() != n))
    refuse("poses", "every array of poses must hold one pose or one per pair");
  std::vector<Eigen::Isometry3d> ba(size_t(pa.size() == 1 ? 0 : n)), bb(size_t(pb.size() == 1 ? 0 : n));
  std::vector<MinkowskiSum> out(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = minkowski_sum_batch(a.data(), pa.chunk(0, n, ba.data()), b.data(), pb.chunk(0, n, bb.data()), n, out.data(), difference, parts,
                            {threads});
  }
  check_batch(s, difference ? "minkowski_difference_batch" : "minkowski_sum_batch");
  return out;
}

}  // namespace

void register_batches(py::module_& m) {
  const char* const threads_doc =
      "threads: 0 one per core, 1 the calling thread alone. out: a result of an earlier call with the same N, refilled\n"
      "in place and returned (a loop of batches then allocates nothing). Runs without the GIL.";
  m.def("proximity_batch", &proximities, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("want") = Want::Witnesses, py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("proximity of a and b under N poses each ((N, 4, 4) arrays, or one pose for all): a namespace of\n"
                     "arrays (intersecting, distance, point_a, point_b, penetration_depth, penetration_direction, max_distance),\n"
                     "N rows each. Blocks of 256 poses run in order from one cache: the same answers on any number of threads.\n") +
         threads_doc)
            .c_str());
  m.def("time_of_impact_batch", &impacts, py::arg("a"), py::arg("a0"), py::arg("a1"), py::arg("b"), py::arg("b0"), py::arg("b1"),
        py::arg("tolerance") = 0.0, py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("time_of_impact of N motions: arrays hit, time, distance, normal, point_a, point_b.\n") + threads_doc).c_str());
  m.def("mesh_distance_batch", &mesh_distances<Octree>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0, py::arg("out") = py::none(),
        (std::string("mesh_distance under N poses: arrays distance, point_a, point_b, triangle_a, triangle_b,\n"
                     "intersecting; one workspace per thread.\n") +
         threads_doc)
            .c_str());
  m.def("mesh_distance_batch", &mesh_distances<ConvexShape>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0, py::arg("out") = py::none(), "mesh_distance of a mesh and a convex shape under N poses.");
  m.def(
      "minkowski_sum_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, false, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      "The sums of N pairs: shapes a[k] and b[k] under poses_a[k] and poses_b[k]; a list of Sum.\n"
      "threads: 0 one per core, 1 the calling thread alone. Runs without the GIL.");
  m.def(
      "minkowski_difference_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, true, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      "The differences of N pairs; a list of Sum. threads as minkowski_sum_batch's.");
}

}  // namespace minksum::python
