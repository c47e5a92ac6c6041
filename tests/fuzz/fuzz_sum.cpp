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

// Grid mode (flag 16): every coordinate snapped to the integers within +-r, r = 1 ... 8, where
// ties are the rule (parallel faces and edges, coplanar points), and the fast path's V, E, F
// checked against the hull of the exact pairwise sums (Qhull, which merges exactly coplanar
// facets of such small integers): an answer, not only a consistent one.
void check_grid_structure(const ConvexPolytope& A, const ConvexPolytope& B, bool diff, const MinkowskiSum& fast) {
  MinkowskiSum hull;
  const Status s = diff ? minkowski_difference(A, B, hull, Method::Hull) : minkowski_sum(A, B, hull, Method::Hull);
  if (s != Status::Ok) fuzz::fail("the hull method failed where the fast path did not");
  if (fast.corrected) fuzz::fail("the fast path needed the corrector on a grid input");
  if (fast.V != hull.V || fast.E != hull.E || fast.F != hull.F) fuzz::fail("V, E, F differ from the hull's on a grid input");
}

// A signed permutation (one of the 48 rotations and reflections of the cube that are proper:
// 24) and a translation of integers, from the input.
Eigen::Isometry3d grid_pose(fuzz::Bytes& in) {
  static const int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
  const uint8_t code = in.take<uint8_t>();
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  p.linear().setZero();
  const int* perm = kPerm[code % 6];
  double sign[3] = {code & 8 ? -1.0 : 1.0, code & 16 ? -1.0 : 1.0, 1};
  sign[2] = (code % 6 < 3 ? 1 : -1) * sign[0] * sign[1];  // determinant +1
  for (int k = 0; k < 3; ++k) p.linear()(k, perm[k]) = sign[k];
  for (int k = 0; k < 3; ++k) p.translation()[k] = double(in.take<int8_t>() % 16);
  return p;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const int na = 1 + in.take<uint8_t>() % 24, nb = 1 + in.take<uint8_t>() % 24;
  const uint8_t flags = in.take<uint8_t>();
  const bool grid = flags & 16;
  const double r = grid ? 1 + in.take<uint8_t>() % 8 : 0;
  const auto coordinate = [&] {
    const double x = in.number();
    return grid ? std::fmod(std::abs(std::isfinite(x) ? std::round(x) : 0.0), 2 * r + 1) - r : x;
  };
  std::vector<Eigen::Vector3d> a, b;
  for (int k = 0; k < na; ++k) a.emplace_back(coordinate(), coordinate(), coordinate());
  for (int k = 0; k < nb; ++k) b.emplace_back(coordinate(), coordinate(), coordinate());
  ConvexPolytope A, B;
  if (polytope_from_points(a, A) != Status::Ok || polytope_from_points(b, B) != Status::Ok) return 0;
  Proximity prox;
  if (proximity(A, B, prox) == Status::Ok) fuzz::check(prox);
  const Method method = grid || flags % 3 == 0 ? Method::Fast : flags % 3 == 1 ? Method::Reference : Method::Hull;
  const bool diff = flags & 4;
  MinkowskiSum m;
  const Status s = diff ? minkowski_difference(A, B, m, method) : minkowski_sum(A, B, m, method);
  if (s != Status::Ok) return 0;  // a status is a clear answer (e.g. DegenerateResult)
  check_planes(m, A.vertices, B.vertices, diff ? -1 : 1);
  if (grid) check_grid_structure(A, B, diff, m);
  // The same operands as prepared shapes under poses read from the rest of the input (a unit
  // quaternion and a translation each; with flag 8, a raw 3x3 matrix for B: rarely a rotation;
  // in grid mode signed permutations and integer translations, which keep every tie exact).
  ConvexShape SA, SB;
  if (shape_from_points(a, SA) != Status::Ok || shape_from_points(b, SB) != Status::Ok) return 0;  // a clear status
  const Eigen::Isometry3d pa = grid ? grid_pose(in) : pose(in, false), pb = grid ? grid_pose(in) : pose(in, flags & 8);
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
  if (grid) {
    ConvexPolytope WA, WB;
    if (polytope_from_points(wa, WA) != Status::Ok || polytope_from_points(wb, WB) != Status::Ok)
      fuzz::fail("a moved grid operand is no longer a polytope");
    check_grid_structure(WA, WB, diff, m);
  }
  return 0;
}
