// The status strings and the checks of the input types: coordinates, boxes, triangles, poses.
#include "core/validate.hpp"

#include <minksum/shape.hpp>

#include <algorithm>
#include <cmath>

namespace minksum {

using Eigen::Vector3d;

const char* to_string(Status s) {
  switch (s) {
    case Status::Ok:
      return "ok";
    case Status::NonFinite:
      return "a coordinate is NaN or Inf";
    case Status::OutOfRange:
      return "a coordinate's magnitude exceeds 1e100";
    case Status::TooFewPoints:
      return "fewer than 3 distinct points";
    case Status::Collinear:
      return "all points are collinear (a segment is not a polytope)";
    case Status::InvalidMesh:
      return "invalid mesh (bad index, short or degenerate face, open or non-manifold)";
    case Status::NotConvex:
      return "the mesh is not convex";
    case Status::InvalidBox:
      return "invalid box (non-positive half extent or non-orthonormal rotation)";
    case Status::DegenerateResult:
      return "the sum of two coplanar flat polytopes is flat, not a solid";
    case Status::HullFailed:
      return "the convex hull (Qhull) failed";
    case Status::InvalidPose:
      return "the pose is not a finite rigid motion (a proper rotation and a translation)";
    case Status::InvalidArgument:
      return "a number is outside its documented range (a negative or NaN margin)";
    case Status::CapacityExceeded:
      return "the result exceeds its fixed capacity";
  }
  return "unknown status";
}

namespace detail {

Status check_coordinates(const Vector3d* pts, size_t n) {
  for (size_t k = 0; k < n; ++k)
    if (!pts[k].allFinite()) return Status::NonFinite;
  for (size_t k = 0; k < n; ++k)
    if (!(pts[k].cwiseAbs().maxCoeff() <= kMaxCoordinate)) return Status::OutOfRange;
  return Status::Ok;
}

double diagonal(const Vector3d* pts, size_t n) {
  Vector3d lo = pts[0], hi = pts[0];
  for (size_t k = 0; k < n; ++k) lo = lo.cwiseMin(pts[k]), hi = hi.cwiseMax(pts[k]);
  return (hi - lo).norm();
}

}  // namespace detail

Status check_box(const Box& box) {
  // One pass over the 15 numbers (a proximity query checks two boxes per call): finite iff
  // x * 0 == 0 for every entry (NaN and Inf give NaN), summed without a branch per entry.
  const double *c = box.center.data(), *h = box.half_extents.data(), *r = box.rotation.data();
  double zero = 0, cmax = 0, hmax = 0;
  for (int k = 0; k < 3; ++k) {
    zero += 0 * c[k] + 0 * h[k] + 0 * r[k] + 0 * r[3 + k] + 0 * r[6 + k];
    cmax = std::max(cmax, std::abs(c[k])), hmax = std::max(hmax, h[k]);
  }
  if (!(zero == 0)) return Status::NonFinite;
  if (!(cmax <= kMaxCoordinate && hmax <= kMaxCoordinate)) return Status::OutOfRange;
  // Positive, and not so small against the box's coordinates that its corners coincide in
  // double (1e-13 relative: about 450 ulps).
  const double floor = 1e-13 * (cmax + hmax);
  if (!(h[0] > floor && h[1] > floor && h[2] > floor)) return Status::InvalidBox;
  // A proper rotation: orthonormal columns x, y, z (to 1e-9) and a right-handed frame.
  const auto dot = [r](int i, int j) { return r[i] * r[j] + r[i + 1] * r[j + 1] + r[i + 2] * r[j + 2]; };
  const double worst = std::max(std::max(std::abs(dot(0, 0) - 1), std::abs(dot(3, 3) - 1)),
                                std::max(std::max(std::abs(dot(6, 6) - 1), std::abs(dot(0, 3))),
                                         std::max(std::abs(dot(0, 6)), std::abs(dot(3, 6)))));
  const double det =
      (r[1] * r[5] - r[2] * r[4]) * r[6] + (r[2] * r[3] - r[0] * r[5]) * r[7] + (r[0] * r[4] - r[1] * r[3]) * r[8];
  if (!(worst <= 1e-9) || det < 0) return Status::InvalidBox;
  return Status::Ok;
}

Status check_triangle(const Triangle& t) {
  const Vector3d pts[3] = {t.a, t.b, t.c};
  if (const Status s = detail::check_coordinates(pts, 3); s != Status::Ok) return s;
  if (t.a == t.b || t.b == t.c || t.a == t.c) return Status::TooFewPoints;
  const double D = detail::diagonal(pts, 3);
  // Relative to the diagonal first: the cross product of raw edges overflows beyond 1e154.
  if (((t.b - t.a) / D).cross((t.c - t.a) / D).norm() <= detail::kLineTol) return Status::Collinear;
  return Status::Ok;
}

[[gnu::flatten]] Status check_pose(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d R = pose.linear();
  const Vector3d t = pose.translation();
  if (!R.allFinite() || !t.allFinite()) return Status::InvalidPose;
  if (!(t.cwiseAbs().maxCoeff() <= kMaxCoordinate)) return Status::InvalidPose;
  // A proper rotation: orthonormal columns (to 1e-9) and a right-handed frame.
  if (!((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9) || !(R.determinant() > 0))
    return Status::InvalidPose;
  return Status::Ok;
}

}  // namespace minksum
