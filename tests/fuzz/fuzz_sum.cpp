// minkowski_sum / minkowski_difference on arbitrary point sets, as polytopes and as prepared
// shapes under poses read from the input: a clear status (InvalidPose for a pose that is not
// rigid), or a valid polytope (Euler, finite planes, every pairwise sum inside every plane
// within the bound); and the proximity of the two polytopes: finite and consistent.
#include "fuzz_common.hpp"

using namespace minksum;

namespace {

// An Ok result: Euler, finite, and every pairwise sum a + sign b inside every plane.
void check_planes(const MinkowskiSum& m, const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                  double sign) {
  if (!m.euler_ok) fuzz::fail("Euler check failed on an Ok result");
  // Rounding is relative to the largest coordinate involved: of the result, or of an operand
  // (a difference of two far-translated operands cancels the translation, not its rounding).
  double size = 1;
  for (const auto* x : {&a, &b})
    for (const auto& p : *x) size = std::max(size, p.cwiseAbs().maxCoeff());
  for (const auto& v : m.vertices) {
    if (!fuzz::finite(v.point)) fuzz::fail("non-finite vertex");
    size = std::max(size, v.point.cwiseAbs().maxCoeff());
  }
  for (const auto& p : m.planes)
    if (!fuzz::finite(p.normal) || !std::isfinite(p.offset)) fuzz::fail("non-finite plane");
  for (const auto& p : a)
    for (const auto& q : b)
      for (const auto& pl : m.planes)
        if (pl.normal.dot(p + sign * q) > pl.offset + 1e-9 * size) fuzz::fail("a pairwise sum is outside a plane");
}

// A pose from the input: a quaternion (normalised; zero reads as the identity) and a
// translation, or with `raw` any 3x3 matrix.
Eigen::Isometry3d pose(fuzz::Bytes& in, bool raw) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  if (raw) {
    for (int k = 0; k < 9; ++k) p.linear()(k / 3, k % 3) = in.number();
  } else {
    Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
    if (q.norm() > 0 && std::isfinite(q.norm())) p.linear() = q.normalized().toRotationMatrix();
  }
  p.translation() = Eigen::Vector3d(in.number(), in.number(), in.number());
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const int na = 1 + in.take<uint8_t>() % 24, nb = 1 + in.take<uint8_t>() % 24;
  const uint8_t flags = in.take<uint8_t>();
  std::vector<Eigen::Vector3d> a, b;
  for (int k = 0; k < na; ++k) a.emplace_back(in.number(), in.number(), in.number());
  for (int k = 0; k < nb; ++k) b.emplace_back(in.number(), in.number(), in.number());
  ConvexPolytope A, B;
  if (polytope_from_points(a, A) != Status::Ok || polytope_from_points(b, B) != Status::Ok) return 0;
  Proximity prox;
  if (proximity(A, B, prox) == Status::Ok) fuzz::check(prox);
  const Method method = flags % 3 == 0 ? Method::Fast : flags % 3 == 1 ? Method::Reference : Method::Hull;
  const bool diff = flags & 4;
  MinkowskiSum m;
  const Status s = diff ? minkowski_difference(A, B, m, method) : minkowski_sum(A, B, m, method);
  if (s != Status::Ok) return 0;  // a status is a clear answer (e.g. DegenerateResult)
  check_planes(m, A.vertices, B.vertices, diff ? -1 : 1);
  // The same operands as prepared shapes under poses read from the rest of the input (a unit
  // quaternion and a translation each; with flag 8, a raw 3x3 matrix for B: rarely a rotation).
  ConvexShape SA, SB;
  if (shape_from_points(a, SA) != Status::Ok || shape_from_points(b, SB) != Status::Ok) return 0;  // a clear status
  const Eigen::Isometry3d pa = pose(in, false), pb = pose(in, flags & 8);
  const Status ps = diff ? minkowski_difference(SA, pa, SB, pb, m) : minkowski_sum(SA, pa, SB, pb, m);
  if (check_pose(pa) != Status::Ok || check_pose(pb) != Status::Ok) {
    if (ps != Status::InvalidPose || m.F != 0) fuzz::fail("a bad pose did not give InvalidPose and an empty result");
    return 0;
  }
  if (ps != Status::Ok) return 0;
  std::vector<Eigen::Vector3d> wa, wb;
  for (const auto& p : SA.polytope().vertices) wa.push_back(pa * p);
  for (const auto& q : SB.polytope().vertices) wb.push_back(pb * q);
  check_planes(m, wa, wb, diff ? -1 : 1);
  return 0;
}
