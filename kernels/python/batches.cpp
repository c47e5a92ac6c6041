// The batches of minksum/parallel.hpp from Python: poses as (N, 4, 4) arrays (or one pose for
// every item), results as arrays of N rows, and the work done without the GIL.

#include <minksum/parallel.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/stl.h>

namespace minksum::python {

namespace {

// N poses from an (N, 4, 4) array, or one from anything pose_of takes. Rigidity is each item's
// to check (the batch reports the first item that fails).
std::vector<Eigen::Isometry3d> poses_of(const py::handle& value, const char* what) {
  const py::array raw = py::array::ensure(value);
  if (value.is_none() || !raw || raw.ndim() != 3) return {pose_of(value, what)};
  const Doubles a = Doubles::ensure(raw);
  if (!a || a.shape(1) != 4 || a.shape(2) != 4) refuse(what, "expected an (N, 4, 4) array of poses");
  const auto r = a.unchecked<3>();
  std::vector<Eigen::Isometry3d> out(size_t(a.shape(0)));
  for (py::ssize_t k = 0; k < a.shape(0); ++k) {
    if (r(k, 3, 0) != 0 || r(k, 3, 1) != 0 || r(k, 3, 2) != 0 || r(k, 3, 3) != 1)
      refuse(what, "pose " + std::to_string(k) + ": the last row of a 4x4 pose must be (0, 0, 0, 1)");
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) out[size_t(k)].matrix()(i, j) = r(k, i, j);
  }
  return out;
}

// The batch's size: every list of poses has it, or one pose.
long batch_size(std::initializer_list<const std::vector<Eigen::Isometry3d>*> lists) {
  long n = 1;
  for (const auto* l : lists) n = std::max(n, long(l->size()));
  for (const auto* l : lists)
    if (l->size() != 1 && long(l->size()) != n) refuse("poses", "every array of poses must hold one pose or the same N");
  return n;
}

Poses span(const std::vector<Eigen::Isometry3d>& p) { return {p.data(), long(p.size())}; }

void check_batch(const BatchStatus& s, const char* what) {
  if (s.status == Status::Ok) return;
  check(s.status, (std::string(what) + ": item " + std::to_string(s.index)).c_str());
}

// Field `get` of every result, as an (N,) array, or (N, 3) for a 3-vector.
template <class T, class Get>
py::array column(const std::vector<T>& items, Get get) {
  using Value = std::decay_t<decltype(get(items[0]))>;
  const py::ssize_t n = py::ssize_t(items.size());
  if constexpr (std::is_same_v<Value, Eigen::Vector3d>) {
    py::array_t<double> out({n, py::ssize_t(3)});
    double* d = out.mutable_data();
    for (const T& item : items) {
      const Eigen::Vector3d v = get(item);
      *d++ = v.x(), *d++ = v.y(), *d++ = v.z();
    }
    return std::move(out);
  } else {
    py::array_t<Value> out(n);
    Value* d = out.mutable_data();
    for (const T& item : items) *d++ = get(item);
    return std::move(out);
  }
}

py::object namespace_of(py::dict fields) { return py::module_::import("types").attr("SimpleNamespace")(**fields); }

py::object proximities(const ConvexShape& a, const py::handle& pose_a, const ConvexShape& b, const py::handle& pose_b,
                       const py::handle& want, int threads) {
  const auto pa = poses_of(pose_a, "poses_a"), pb = poses_of(pose_b, "poses_b");
  const long n = batch_size({&pa, &pb});
  const Want w = want_of(want);
  std::vector<Proximity> out(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = proximity_batch(a, span(pa), b, span(pb), n, out.data(), w, {threads});
  }
  check_batch(s, "proximity_batch");
  py::dict f;
  f["intersecting"] = column(out, [](const Proximity& p) { return p.intersecting; });
  f["distance"] = column(out, [](const Proximity& p) { return p.distance; });
  f["point_a"] = column(out, [](const Proximity& p) { return p.point_a; });
  f["point_b"] = column(out, [](const Proximity& p) { return p.point_b; });
  f["penetration_depth"] = column(out, [](const Proximity& p) { return p.penetration_depth; });
  f["penetration_direction"] = column(out, [](const Proximity& p) { return p.penetration_direction; });
  f["max_distance"] = column(out, [](const Proximity& p) { return p.max_distance; });
  return namespace_of(f);
}

py::object impacts(const ConvexShape& a, const py::handle& a0, const py::handle& a1, const ConvexShape& b, const py::handle& b0,
                   const py::handle& b1, double tolerance, int threads) {
  const auto p0 = poses_of(a0, "a0"), p1 = poses_of(a1, "a1"), q0 = poses_of(b0, "b0"), q1 = poses_of(b1, "b1");
  const long n = batch_size({&p0, &p1, &q0, &q1});
  std::vector<TimeOfImpact> out(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = time_of_impact_batch(a, span(p0), span(p1), b, span(q0), span(q1), n, out.data(), tolerance, {threads});
  }
  check_batch(s, "time_of_impact_batch");
  py::dict f;
  f["hit"] = column(out, [](const TimeOfImpact& t) { return t.hit; });
  f["time"] = column(out, [](const TimeOfImpact& t) { return t.time; });
  f["distance"] = column(out, [](const TimeOfImpact& t) { return t.distance; });
  f["normal"] = column(out, [](const TimeOfImpact& t) { return t.normal; });
  f["point_a"] = column(out, [](const TimeOfImpact& t) { return t.point_a; });
  f["point_b"] = column(out, [](const TimeOfImpact& t) { return t.point_b; });
  return namespace_of(f);
}

template <class Other>
py::object mesh_distances(const Octree& a, const py::handle& pose_a, const Other& b, const py::handle& pose_b, int threads) {
  const auto pa = poses_of(pose_a, "poses_a"), pb = poses_of(pose_b, "poses_b");
  const long n = batch_size({&pa, &pb});
  std::vector<MeshDistance> out(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = mesh_distance_batch(a, span(pa), b, span(pb), n, out.data(), {threads});
  }
  check_batch(s, "mesh_distance_batch");
  py::dict f;
  f["distance"] = column(out, [](const MeshDistance& d) { return d.distance; });
  f["point_a"] = column(out, [](const MeshDistance& d) { return d.point_a; });
  f["point_b"] = column(out, [](const MeshDistance& d) { return d.point_b; });
  f["triangle_a"] = column(out, [](const MeshDistance& d) { return d.triangle_a; });
  f["triangle_b"] = column(out, [](const MeshDistance& d) { return d.triangle_b; });
  f["intersecting"] = column(out, [](const MeshDistance& d) { return d.intersecting; });
  return namespace_of(f);
}

std::vector<MinkowskiSum> sums(const std::vector<ConvexShape>& a, const py::handle& pose_a, const std::vector<ConvexShape>& b,
                               const py::handle& pose_b, bool difference, SumParts parts, int threads) {
  if (a.size() != b.size()) refuse("b", "expected as many shapes as a");
  const auto pa = poses_of(pose_a, "poses_a"), pb = poses_of(pose_b, "poses_b");
  const long n = long(a.size());
  if ((pa.size() != 1 && long(pa.size()) != n) || (pb.size() != 1 && long(pb.size()) != n))
    refuse("poses", "every array of poses must hold one pose or one per pair");
  std::vector<MinkowskiSum> out(static_cast<size_t>(n));
  BatchStatus s;
  {
    py::gil_scoped_release unlocked;
    s = minkowski_sum_batch(a.data(), span(pa), b.data(), span(pb), n, out.data(), difference, parts, {threads});
  }
  check_batch(s, difference ? "minkowski_difference_batch" : "minkowski_sum_batch");
  return out;
}

}  // namespace

void register_batches(py::module_& m) {
  const char* const threads_doc = "threads: 0 one per core, 1 the calling thread alone. Runs without the GIL.";
  m.def("proximity_batch", &proximities, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("want") = Want::Witnesses, py::arg("threads") = 0,
        (std::string("proximity of a and b under N poses each ((N, 4, 4) arrays, or one pose for all): a namespace of\n"
                     "arrays (intersecting, distance, point_a, point_b, penetration_depth, penetration_direction, max_distance),\n"
                     "N rows each. Blocks of 256 poses run in order from one cache: the same answers on any number of threads.\n") +
         threads_doc)
            .c_str());
  m.def("time_of_impact_batch", &impacts, py::arg("a"), py::arg("a0"), py::arg("a1"), py::arg("b"), py::arg("b0"), py::arg("b1"),
        py::arg("tolerance") = 0.0, py::arg("threads") = 0,
        (std::string("time_of_impact of N motions: arrays hit, time, distance, normal, point_a, point_b.\n") + threads_doc).c_str());
  m.def("mesh_distance_batch", &mesh_distances<Octree>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0,
        (std::string("mesh_distance under N poses: arrays distance, point_a, point_b, triangle_a, triangle_b,\n"
                     "intersecting; one workspace per thread.\n") +
         threads_doc)
            .c_str());
  m.def("mesh_distance_batch", &mesh_distances<ConvexShape>, py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"),
        py::arg("threads") = 0, "mesh_distance of a mesh and a convex shape under N poses.");
  m.def(
      "minkowski_sum_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, false, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      (std::string("The sums of N pairs: shapes a[k] and b[k] under poses_a[k] and poses_b[k]; a list of Sum.\n") + threads_doc).c_str());
  m.def(
      "minkowski_difference_batch",
      [](const std::vector<ConvexShape>& a, const py::handle& pa, const std::vector<ConvexShape>& b, const py::handle& pb,
         SumParts parts, int threads) { return sums(a, pa, b, pb, true, parts, threads); },
      py::arg("a"), py::arg("poses_a"), py::arg("b"), py::arg("poses_b"), py::arg("parts") = SumParts::Whole, py::arg("threads") = 0,
      (std::string("The differences of N pairs; a list of Sum.\n") + threads_doc).c_str());
}

}  // namespace minksum::python
