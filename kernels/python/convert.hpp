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

/// Raises minksum.Error(message) carrying `s` (a message more precise than the status's own).
[[noreturn]] void raise(Status s, const std::string& message);

/// A pose and the argument it came from.
struct NamedPose {
  const Eigen::Isometry3d& pose;  ///< the pose
  const char* name;               ///< its argument
};

/// check(s, what), but an InvalidPose names the first of `poses` that is not rigid and what is
/// wrong with it (pose_problem): the library checks the poses inside the call, so they are not
/// checked twice on the way in.
void check(Status s, const char* what, std::initializer_list<NamedPose> poses);

/// What keeps `pose` from being rigid, in words with the numbers ("" if it is rigid).
std::string pose_problem(const Eigen::Isometry3d& pose);

/// How far from a rotation a float32 (or narrower) pose may be and still be taken, projected
/// onto the nearest rotation (rotation_deviation): about 80 float32 roundings.
constexpr double kFloat32PoseTolerance = 1e-5;

/// A file path from a str, bytes or os.PathLike (os.fsdecode).
std::string path_of(const py::handle& value);

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
/// (rotation 3x3, translation 3). A rotation given in float32 is projected onto the nearest
/// rotation where it is within kFloat32PoseTolerance of one (rounded to float32, no rotation is
/// one to 1e-9). Its rigidity is the call's to check (see check).
Eigen::Isometry3d pose_of(const py::handle& value, const char* what);

/// Whether `value` is an array (or array-like) of floats narrower than double.
bool single_precision(const py::handle& value);

/// `r` projected onto the nearest rotation where it is within kFloat32PoseTolerance of one.
Eigen::Matrix3d float32_rotation(const Eigen::Matrix3d& r);

/// `want`, checked to be a combination of the Want levels (Want(64) is not).
Want want_of(Want want);

/// The fields of `p` that `want` did not ask for set to NaN: the library leaves them at 0,
/// which is a real distance (C++ documents it; Python says "not computed").
void not_asked(Want want, Proximity& p);

/// A 3-vector as a new (3,) float64 array.
py::array_t<double> array_of(const Eigen::Vector3d& v);

/// n points as a new (n, 3) float64 array.
py::array_t<double> array_of(const Eigen::Vector3d* points, long n);

/// The binding's exception type (set once by the module).
extern PyObject* error_type;

}  // namespace minksum::python
