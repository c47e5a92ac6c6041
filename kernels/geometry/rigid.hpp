// A rigid pose as the kernels apply it to body-frame data (internal): the one piece of pose
// arithmetic that the queries' posed shapes (query/views.hpp), the overlay's operands
// (sum/overlay.hpp) and the mesh queries (mesh/) share. Eigen::Isometry3d stays at the API.
#pragma once

#include <Eigen/Geometry>

#include <cstddef>

namespace minksum::detail {

/// x' = R x + t, with directions turned by R. `turned` is false for the identity rotation,
/// which leaves directions as stored (exactly: the overlay's ties stay exact).
struct Rigid {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  bool turned = false;

  Rigid() = default;
  /// The pose x' = R x + t (R a rotation, or minus one for a negated operand).
  Rigid(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& translation)
      : R(rotation), t(translation), turned(rotation != Eigen::Matrix3d::Identity()) {}
  /// The pose of an Isometry3d (the API's type).
  explicit Rigid(const Eigen::Isometry3d& pose) : Rigid(pose.linear(), pose.translation()) {}
  /// As an Isometry3d, for the API's calls.
  Eigen::Isometry3d isometry() const {
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = R, p.translation() = t;
    return p;
  }

  /// R x + t, written out: Eigen's product is not always inlined in the support loops.
  Eigen::Vector3d point(const Eigen::Vector3d& x) const {
    return {R(0, 0) * x[0] + R(0, 1) * x[1] + R(0, 2) * x[2] + t[0],
            R(1, 0) * x[0] + R(1, 1) * x[1] + R(1, 2) * x[2] + t[1],
            R(2, 0) * x[0] + R(2, 1) * x[1] + R(2, 2) * x[2] + t[2]};
  }
  /// R d.
  Eigen::Vector3d turn(const Eigen::Vector3d& d) const { return turned ? Eigen::Vector3d(R * d) : d; }
  /// A world direction in the body frame, R^T d: then d . x' = to_body(d) . x + shift(d), so a
  /// support pass reads the stored vertices with one product instead of a pose per vertex.
  Eigen::Vector3d to_body(const Eigen::Vector3d& d) const { return R.transpose() * d; }
  /// d . t.
  double shift(const Eigen::Vector3d& d) const { return d.dot(t); }
  /// The body-frame plane n . x = offset placed: its normal R n and its offset offset + R n . t.
  void plane(const Eigen::Vector3d& n, double offset, Eigen::Vector3d& n_out, double& offset_out) const {
    n_out = turn(n), offset_out = offset + n_out.dot(t);
  }
  /// A world point in the body frame, R^T (x - t).
  Eigen::Vector3d body_point(const Eigen::Vector3d& x) const { return R.transpose() * (x - t); }
  /// x' for n points stored by coordinate (x, y, z) into out[0..2], a row of R at a time (the
  /// loops vectorise).
  void place(const double* x, const double* y, const double* z, std::size_t n, double* const (&out)[3]) const {
    for (int r = 0; r < 3; ++r) {
      const double m0 = R(r, 0), m1 = R(r, 1), m2 = R(r, 2), c = t[r];
      double* p = out[r];
      for (std::size_t k = 0; k < n; ++k) p[k] = m0 * x[k] + m1 * y[k] + m2 * z[k] + c;
    }
  }
};

}  // namespace minksum::detail
