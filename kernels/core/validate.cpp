// The status strings and the checks of the input types: coordinates, boxes, triangles, poses.
#include "core/validate.hpp"

#include <minksum/shape.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/LU>

namespace minksum {

using Eigen::Vector3d;

const char* to_string(Status s) {
  switch (s) {
    case Status::Ok:
      return "ok";
    case Status::NonFinite:
      return "a coordinate is NaN or Inf";
    case Status::OutOfRange:
      return "a coordinate's magnitude exceeds 1e100, the shape is under 1e-100 across, or its coordinates span more than 2^300 (products would overflow or underflow)";
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
      return "the sum is not a solid (two coplanar flat polytopes without a radius)";
    case Status::HullFailed:
      return "the convex hull failed";
    case Status::InvalidPose:
      return "the pose is not a rigid motion (a proper rotation, every entry of R^T R - I within 1e-9, and a finite translation within 1e100)";
    case Status::InvalidArgument:
      return "a number is outside its documented range (a negative, NaN or infinite margin, tolerance or half length; a radius that is not positive and finite; an octree's leaf size under 1)";
    case Status::CapacityExceeded:
      return "the result exceeds its fixed capacity";
    case Status::Unsupported:
      return "this operation does not take this kind of shape yet (a sphere, a capsule or a radius)";
    case Status::EmptyMesh:
      return "the mesh has no triangles (a point cloud has its own builder), or the point cloud no points";
    case Status::WorkspaceMismatch:
      return "the workspace was not made for these meshes (make_workspace with the call's meshes)";
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

bool proper_rotation(const double* r, int stride) {
  // Orthonormal columns x, y, z (to 1e-9: six dot products) and right-handed ((x × y) . z > 0,
  // which is ±1 for orthonormal columns). A conjunction of comparisons, so that a NaN or Inf
  // entry fails.
  const double *x = r, *y = r + stride, *z = r + 2 * stride;
  const auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  const double det =
      (x[1] * y[2] - x[2] * y[1]) * z[0] + (x[2] * y[0] - x[0] * y[2]) * z[1] + (x[0] * y[1] - x[1] * y[0]) * z[2];
  const double tol = kRotationTolerance;
  return std::abs(dot(x, x) - 1) <= tol && std::abs(dot(y, y) - 1) <= tol && std::abs(dot(z, z) - 1) <= tol &&
         std::abs(dot(x, y)) <= tol && std::abs(dot(x, z)) <= tol && std::abs(dot(y, z)) <= tol && det > 0;
}

}  // namespace detail

Status check_box(const Box& box) {
  // One pass over the 15 numbers (a proximity query checks two boxes per call): finite iff
  // x * 0 == 0 for every entry (NaN and Inf give NaN), summed without a branch per entry.
  const double *c = box.center.data(), *h = box.half_extents.data(), *r = box.rotation.data();
  double zero = 0;
  for (int k = 0; k < 3; ++k) zero += 0 * c[k] + 0 * h[k] + 0 * r[k] + 0 * r[3 + k] + 0 * r[6 + k];
  if (!(zero == 0)) return Status::NonFinite;
  const double cmax = std::max({std::abs(c[0]), std::abs(c[1]), std::abs(c[2])});
  const double hmax = std::max({h[0], h[1], h[2]});
  if (!(cmax <= kMaxCoordinate && hmax <= kMaxCoordinate)) return Status::OutOfRange;
  // Positive, and not so small against the box's coordinates that its corners coincide in
  // double (1e-13 relative: about 450 ulps).
  const double floor = 1e-13 * (cmax + hmax);
  if (!(h[0] > floor && h[1] > floor && h[2] > floor)) return Status::InvalidBox;
  return detail::proper_rotation(r, 3) ? Status::Ok : Status::InvalidBox;
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

double rotation_deviation(const Eigen::Matrix3d& r) {
  if (!r.allFinite() || !(r.determinant() > 0)) return std::numeric_limits<double>::infinity();
  return (r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
}

Eigen::Matrix3d nearest_rotation(const Eigen::Matrix3d& r) {
  if (!(rotation_deviation(r) <= 0.1)) return r;
  // X <- (X + X^-T) / 2 converges quadratically to the orthogonal polar factor, the nearest
  // orthogonal matrix in the Frobenius norm (Higham, SIAM J. Sci. Stat. Comput. 7(4), 1986); det > 0
  // keeps it a rotation. From 0.1 off, six steps reach rounding.
  Eigen::Matrix3d x = r;
  for (int k = 0; k < 6; ++k) x = 0.5 * (x + x.inverse().transpose());
  return x;
}

Status check_pose(const Eigen::Isometry3d& pose) {
  const double* t = pose.translation().data();
  // (NaN and Inf fail these comparisons, and proper_rotation's.)
  const bool placed =
      std::abs(t[0]) <= kMaxCoordinate && std::abs(t[1]) <= kMaxCoordinate && std::abs(t[2]) <= kMaxCoordinate;
  return placed && detail::proper_rotation(pose.linear().data(), int(pose.linear().outerStride()))
             ? Status::Ok
             : Status::InvalidPose;
}

}  // namespace minksum
