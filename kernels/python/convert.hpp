// The Python module's conversions at its boundary: NumPy arrays and poses in, arrays out, and a
// Status that is not Ok raised as minksum.Error. Each conversion checks the array's shape and
// dtype and says which argument was wrong; the library checks the values (NaN, rigidity).
#pragma once

#include <minksum/query.hpp>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <initializer_list>
#include <string>
#include <vector>

namespace minksum::python {

namespace py = pybind11;

/// A float64, C-ordered copy or view of any array-like (lists, ints, Fortran order: converted).
using Doubles = py::array_t<double, py::array::c_style | py::array::forcecast>;

/// Raises minksum.Error (a ValueError) carrying `s`, unless it is Ok.
void check(Status s, const char* what);

/// A pose and the argument it came from.
struct NamedPose {
  const Eigen::Isometry3d& pose;  ///< the pose
  const char* name;               ///< its argument
};

/// check(s, what), but an InvalidPose names the first of `poses` that is not rigid: the library
/// checks the poses inside the call, so they are not checked twice on the way in.
void check(Status s, const char* what, std::initializer_list<NamedPose> poses);

/// Raises ValueError("<what>: <message>").
[[noreturn]] void refuse(const char* what, const std::string& message);

/// An (n, 3) array of points (n >= min_rows).
std::vector<Eigen::Vector3d> points_of(const py::handle& array, const char* what, long min_rows = 0);

/// A 3-vector from a sequence or array of 3 numbers.
Eigen::Vector3d vector_of(const py::handle& value, const char* what);

/// A 3x3 matrix.
Eigen::Matrix3d matrix_of(const py::handle& value, const char* what);

/// An (m, 3) integer array of triangle indices, each in [0, vertex_count).
std::vector<std::array<int, 3>> triangles_of(const py::handle& array, const char* what, long vertex_count);

/// A pose: None (the identity), a 4x4 array with last row (0, 0, 0, 1), or a pair
/// (rotation 3x3, translation 3). Its rigidity is the call's to check (see check).
Eigen::Isometry3d pose_of(const py::handle& value, const char* what);

/// `want`, checked to be a combination of the Want levels (Want(64) is not).
Want want_of(Want want);

/// A 3-vector as a new (3,) float64 array.
py::array_t<double> array_of(const Eigen::Vector3d& v);

/// n points as a new (n, 3) float64 array.
py::array_t<double> array_of(const Eigen::Vector3d* points, long n);

/// The binding's exception type (set once by the module).
extern PyObject* error_type;

}  // namespace minksum::python
