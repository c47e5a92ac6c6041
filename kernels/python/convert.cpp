#include "python/convert.hpp"

#include <minksum/shape.hpp>

#include <climits>
#include <limits>

namespace minksum::python {

PyObject* error_type = nullptr;

void raise(Status s, const std::string& message) {
  py::object error = py::reinterpret_borrow<py::object>(error_type)(message);
  error.attr("status") = py::cast(s);
  PyErr_SetObject(error_type, error.ptr());
  throw py::error_already_set();
}

void check(Status s, const char* what) {
  if (s != Status::Ok) raise(s, std::string(what) + ": " + to_string(s));
}

std::string pose_problem(const Eigen::Isometry3d& pose) {
  if (check_pose(pose) == Status::Ok) return "";
  const auto number = [](double x) { return std::string(py::repr(py::float_(x))); };
  if (!pose.matrix().allFinite()) return "not a rigid motion: an entry is NaN or infinite";
  const double far = pose.translation().cwiseAbs().maxCoeff();
  if (far > kMaxCoordinate) return "not a rigid motion: its translation " + number(far) + " exceeds 1e100";
  if (!(pose.linear().determinant() > 0))
    return "not a rigid motion: its rotation's determinant is " + number(pose.linear().determinant()) +
           " (a reflection or a collapse)";
  return "not a rigid motion: its rotation is " + number(rotation_deviation(pose.linear())) +
         " from a rotation (the largest entry of R^T R - I; the tolerance is 1e-09, and a float32 rotation within 1e-05 is "
         "projected onto the nearest one)";
}

void check(Status s, const char* what, std::initializer_list<NamedPose> poses) {
  if (s == Status::InvalidPose)
    for (const NamedPose& p : poses)
      if (const std::string problem = pose_problem(p.pose); !problem.empty()) raise(s, std::string(p.name) + ": " + problem);
  check(s, what);
}

bool single_precision(const py::handle& value) {
  if (!py::isinstance<py::array>(value)) return false;  // (lists and scalars are Python's doubles)
  const py::dtype d = py::reinterpret_borrow<py::array>(value).dtype();
  return d.kind() == 'f' && d.itemsize() < 8;
}

Eigen::Matrix3d float32_rotation(const Eigen::Matrix3d& r) {
  return rotation_deviation(r) <= kFloat32PoseTolerance ? nearest_rotation(r) : r;
}

std::string path_of(const py::handle& value) {
  return py::module_::import("os").attr("fsdecode")(value).cast<std::string>();
}

void refuse(const char* what, const std::string& message) { throw py::value_error(std::string(what) + ": " + message); }

namespace {

std::string shape_text(const py::array& a) {
  std::string text = "(";
  for (py::ssize_t k = 0; k < a.ndim(); ++k) text += (k ? ", " : "") + std::to_string(a.shape(k));
  return text + (a.ndim() == 1 ? ",)" : ")");
}

// Numbers only: a bool, an object or a string array is refused rather than converted.
Doubles doubles_of(const py::handle& value, const char* what) {
  const py::array raw = py::array::ensure(value);
  if (!raw) refuse(what, "expected an array of numbers");
  const char kind = raw.dtype().kind();
  if (kind != 'f' && kind != 'i' && kind != 'u') refuse(what, "expected an array of numbers, got dtype " + std::string(py::str(raw.dtype())));
  return Doubles::ensure(raw);
}

Doubles rows_of_three(const py::handle& value, const char* what, long min_rows) {
  Doubles a = doubles_of(value, what);
  if (a.ndim() != 2 || a.shape(1) != 3) refuse(what, "expected an (n, 3) array, got shape " + shape_text(a));
  if (a.shape(0) < min_rows) refuse(what, "expected at least " + std::to_string(min_rows) + " rows, got " + std::to_string(a.shape(0)));
  return a;
}

}  // namespace

std::vector<Eigen::Vector3d> points_of(const py::handle& array, const char* what, long min_rows) {
  const Doubles a = rows_of_three(array, what, min_rows);
  const auto r = a.unchecked<2>();
  std::vector<Eigen::Vector3d> out(size_t(a.shape(0)));
  for (py::ssize_t k = 0; k < a.shape(0); ++k) out[size_t(k)] = {r(k, 0), r(k, 1), r(k, 2)};
  return out;
}

Eigen::Vector3d vector_of(const py::handle& value, const char* what) {
  const Doubles a = doubles_of(value, what);
  if (a.ndim() != 1 || a.shape(0) != 3) refuse(what, "expected 3 numbers, got shape " + shape_text(a));
  return {a.at(0), a.at(1), a.at(2)};
}

Eigen::Matrix3d matrix_of(const py::handle& value, const char* what) {
  const Doubles a = doubles_of(value, what);
  if (a.ndim() != 2 || a.shape(0) != 3 || a.shape(1) != 3) refuse(what, "expected a 3x3 array, got shape " + shape_text(a));
  Eigen::Matrix3d m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = a.at(r, c);
  return m;
}

std::vector<std::array<int, 3>> triangles_of(const py::handle& array, const char* what, long vertex_count) {
  const py::array raw = py::array::ensure(array);
  if (!raw) refuse(what, "expected an (m, 3) integer array");
  const char kind = raw.dtype().kind();
  if (kind != 'i' && kind != 'u') refuse(what, "expected an integer array, got dtype " + std::string(py::str(raw.dtype())));
  // Wider than int: an index past INT_MAX is out of range, not wrapped.
  const auto a = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(raw);
  if (a.ndim() != 2 || a.shape(1) != 3) refuse(what, "expected an (m, 3) array, got shape " + shape_text(a));
  const auto r = a.unchecked<2>();
  std::vector<std::array<int, 3>> out(size_t(a.shape(0)));
  for (py::ssize_t k = 0; k < a.shape(0); ++k)
    for (int c = 0; c < 3; ++c) {
      const long long i = r(k, c);
      if (i < 0 || i >= vertex_count)
        refuse(what, "triangle " + std::to_string(k) + " has index " + std::to_string(i) + ", outside [0, " +
                         std::to_string(vertex_count) + ")");
      out[size_t(k)][size_t(c)] = int(i);
    }
  return out;
}

namespace {

// A 4x4 pose from 16 doubles, row-major.
Eigen::Isometry3d pose_from_rows(const double* m, const char* what) {
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) refuse(what, "the last row of a 4x4 pose must be (0, 0, 0, 1)");
  Eigen::Isometry3d pose;
  pose.matrix() = Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>>(m);
  return pose;
}

}  // namespace

Eigen::Isometry3d pose_of(const py::handle& value, const char* what) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (value.is_none()) return pose;
  if (Doubles::check_(value)) {  // a C-ordered float64 array, read in place: the common case, fast
    const auto a = py::reinterpret_borrow<Doubles>(value);
    if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
      refuse(what, "expected a 4x4 array or a pair (rotation 3x3, translation 3), got shape " + shape_text(a));
    pose = pose_from_rows(a.data(), what);
  } else if ((py::isinstance<py::tuple>(value) || py::isinstance<py::list>(value)) && py::len(value) == 2) {
    // A pair (rotation, translation); any other sequence is read as a 4x4 array (nested lists).
    const py::sequence pair = py::reinterpret_borrow<py::sequence>(value);
    pose.linear() = matrix_of(pair[0], what);
    pose.translation() = vector_of(pair[1], what);
    if (single_precision(pair[0])) pose.linear() = float32_rotation(pose.linear());
  } else {
    const Doubles a = doubles_of(value, what);
    if (a.ndim() != 2 || a.shape(0) != 4 || a.shape(1) != 4)
      refuse(what, "expected a 4x4 array or a pair (rotation 3x3, translation 3), got shape " + shape_text(a));
    pose = pose_from_rows(a.data(), what);
    if (single_precision(value)) pose.linear() = float32_rotation(pose.linear());
  }
  return pose;
}

Want want_of(Want want) {
  if (unsigned(want) == 0 || unsigned(want) > unsigned(Want::All)) refuse("want", "expected a Want or a combination of them");
  return want;
}

void not_asked(Want want, Proximity& p) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::Vector3d none = Eigen::Vector3d::Constant(nan);
  if (!has(want, Want::Distance)) p.distance = p.penetration_depth = nan, p.penetration_direction = none;
  if (!has(want, Want::Witnesses)) p.point_a = p.point_b = none;
  if (!has(want, Want::MaxDistance)) p.max_distance = nan, p.far_a = p.far_b = none;
}

py::array_t<double> array_of(const Eigen::Vector3d& v) {
  py::array_t<double> out(3);
  std::copy(v.data(), v.data() + 3, out.mutable_data());
  return out;
}

py::array_t<double> array_of(const Eigen::Vector3d* points, long n) {
  py::array_t<double> out({py::ssize_t(n), py::ssize_t(3)});
  double* d = out.mutable_data();
  for (long k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) d[3 * k + c] = points[k][c];
  return out;
}

}  // namespace minksum::python
