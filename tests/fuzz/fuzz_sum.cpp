// minkowski_sum / minkowski_difference on arbitrary point sets, as polytopes and as prepared
// shapes under poses read from the input: a clear status (InvalidPose for a pose that is not
// rigid), or the sum itself: Euler, finite planes, every pairwise sum inside every plane, every
// plane touching the sum (its loop's vertices on it), every vertex the pairwise sum its (i, j)
// names, all within the bound; on lattice input the V, E, F of the hull of the pairwise sums
// and of the reference path; and the proximity of the two polytopes: finite and consistent.
#include "fuzz_common.hpp"

using namespace minksum;

namespace {

// An Ok result is the sum: Euler, finite, every pairwise sum a + sign b inside every plane,
// every vertex the pairwise sum of its pair (i, j), and every plane tight (its loop on it: a
// plane pushed outward, or a facet whose loop strays off it, fails).
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
  const double tol = 1e-9 * size;
  const int na = int(a.size()), nb = int(b.size());
  for (const auto& v : m.vertices) {
    if (v.i < 0 || v.i >= na || v.j < 0 || v.j >= nb) fuzz::fail("a vertex's pair (i, j) out of range");
    if ((v.point - (a[v.i] + sign * b[v.j])).cwiseAbs().maxCoeff() > tol)
      fuzz::fail("a vertex is not the sum of its pair");
  }
  if (int(m.planes.size()) != m.F || int(m.loop_start.size()) != m.F + 1)
    fuzz::fail("F, planes and loop offsets disagree");
  for (int k = 0; k < m.F; ++k) {
    const SumPlane& pl = m.planes[k];
    if (m.facet(k).size() < 3) fuzz::fail("a facet with fewer than 3 vertices");
    for (int v : m.facet(k)) {
      if (v < 0 || v >= int(m.vertices.size())) fuzz::fail("a loop index out of range");
      if (std::abs(pl.normal.dot(m.vertices[v].point) - pl.offset) > tol)
        fuzz::fail("a facet's vertex is off its plane");
    }
  }
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
  if (fast.corrected) fuzz::fail("the fast path needed the corrector on a grid input");
  for (Method other : {Method::Hull, Method::Reference}) {
    MinkowskiSum m;
    const Status s = diff ? minkowski_difference(A, B, m, other) : minkowski_sum(A, B, m, other);
    if (s != Status::Ok) fuzz::fail("the hull or reference method failed where the fast path did not");
    if (fast.V != m.V || fast.E != m.E || fast.F != m.F) {
      std::fprintf(stderr, "fast V %d E %d F %d; %s V %d E %d F %d\n", fast.V, fast.E, fast.F,
                   other == Method::Hull ? "hull" : "reference", m.V, m.E, m.F);
      fuzz::fail("V, E, F differ from the hull's or the reference path's on a grid input");
    }
  }
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
