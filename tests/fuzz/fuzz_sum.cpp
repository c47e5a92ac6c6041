// minkowski_sum / minkowski_difference on arbitrary point sets, as polytopes and as prepared
// shapes under poses read from the input: a clear status (InvalidPose for a pose that is not
// rigid), or the sum itself: Euler, finite planes, every pairwise sum inside every plane, every
// plane touching the sum (its loop's vertices on it), every vertex the pairwise sum its (i, j)
// names, all within the bound; on lattice input the exact hull of the pairwise sums, certified
// in integer arithmetic from the output (check_grid_structure); and the proximity of the two
// polytopes: finite and consistent.
#include "fuzz_common.hpp"

#include <map>

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
// ties are the rule (parallel faces and edges, coplanar points). The fast path's answer is
// certified the exact hull of the pairwise sums in integer arithmetic, from its output alone
// (no other path of the library): a closed surface (every directed edge of a loop has its
// twin, V - E + F = 2 counted from the loops), each vertex a pairwise sum, each facet's loop
// exactly coplanar with no three consecutive vertices collinear, every pairwise sum exactly on
// the inner side of every facet, and no two facets across an edge coplanar. A closed convex
// surface through points of the set that holds the whole set is its hull, with coplanar facets
// merged: an answer, not only a consistent one.
using Int3 = Eigen::Matrix<long long, 3, 1>;

Int3 exact(const Eigen::Vector3d& v) {
  return Int3(std::llround(v.x()), std::llround(v.y()), std::llround(v.z()));
}

void check_grid_structure(const ConvexPolytope& A, const ConvexPolytope& B, bool diff, const MinkowskiSum& fast) {
  if (fast.corrected) fuzz::fail("the fast path needed the corrector on a grid input");
  const long long sign = diff ? -1 : 1;
  std::vector<Int3> sums;
  for (const auto& p : A.vertices)
    for (const auto& q : B.vertices) sums.push_back(exact(p) + sign * exact(q));
  std::vector<Int3> vertex;
  for (const auto& v : fast.vertices) {
    vertex.push_back(exact(v.point));
    if (vertex.back().cast<double>() != v.point) fuzz::fail("a grid sum's vertex is not an integer point");
  }
  std::map<std::pair<int, int>, int> edges;  // directed loop edge -> its facet
  std::vector<Int3> normal(size_t(fast.F));
  for (int k = 0; k < fast.F; ++k) {
    const Loop loop = fast.facet(k);
    const int n = int(loop.size());
    Int3 nk = Int3::Zero();  // a normal from the first non-collinear corner
    for (int c = 0; c < n; ++c) {
      const Int3 &p = vertex[size_t(loop[c])], &q = vertex[size_t(loop[(c + 1) % n])], &r = vertex[size_t(loop[(c + 2) % n])];
      const Int3 turn = (q - p).cross(r - q);
      if (turn.isZero()) fuzz::fail("three consecutive vertices of a grid facet are collinear");
      if (nk.isZero()) nk = turn;
      if (turn.dot(nk) <= 0) fuzz::fail("a grid facet's loop is not convex");
      if (!edges.emplace(std::pair{loop[c], loop[(c + 1) % n]}, k).second) fuzz::fail("a directed edge in two loops");
    }
    for (int c = 0; c < n; ++c)
      if (nk.dot(vertex[size_t(loop[c])] - vertex[size_t(loop[0])]) != 0) fuzz::fail("a grid facet is not planar");
    for (const Int3& x : sums)
      if (nk.dot(x - vertex[size_t(loop[0])]) > 0) fuzz::fail("a pairwise sum lies outside a grid facet");
    normal[size_t(k)] = nk;
  }
  for (const auto& [e, k] : edges) {
    const auto twin = edges.find({e.second, e.first});
    if (twin == edges.end()) fuzz::fail("a grid sum's surface is not closed");
    if (normal[size_t(k)].cross(normal[size_t(twin->second)]).isZero()) fuzz::fail("two coplanar grid facets not merged");
  }
  const long long E = static_cast<long long>(edges.size()) / 2;
  if (static_cast<long long>(fast.vertices.size()) - E + fast.F != 2 || fast.V != int(fast.vertices.size()) || fast.E != E)
    fuzz::fail("V - E + F is not 2, counted from the loops");
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
