// minkowski_sum / minkowski_difference on arbitrary point sets, as polytopes and as prepared
// shapes under poses read from the input: a clear status (InvalidPose for a pose that is not
// rigid), or the sum itself: Euler, finite planes, every pairwise sum inside every plane, every
// plane touching the sum (its loop's vertices on it), every vertex the pairwise sum its (i, j)
// names, all within the bound; on lattice input the exact hull of the pairwise sums, certified
// in integer arithmetic from the output (check_grid_structure); the small overlay's tables
// against the walks where they answer; and the proximity of the two polytopes: finite and
// consistent.
#include "fuzz_common.hpp"

#include <gmpxx.h>

#include <array>
#include <map>
#include <set>
#include <tuple>

#include "shape/shape_data.hpp"
#include "sum/overlay.hpp"

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
  for (const auto& p : m.planes) {
    if (!fuzz::finite(p.normal) || !std::isfinite(p.offset)) fuzz::fail("non-finite plane");
    if (std::abs(p.normal.norm() - 1) > 1e-12) fuzz::fail("a plane's normal is not a unit vector");
  }
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

// The planes level of the same posed sum: the whole sum's planes in its order, normals bit for
// bit, offsets within rounding, each pair (a_i + s b_j) on its plane; no vertices nor loops.
// The vertices level: the whole sum without its loops.
void check_levels(const ConvexShape& SA, const Eigen::Isometry3d& pa, const ConvexShape& SB,
                        const Eigen::Isometry3d& pb, bool diff, const MinkowskiSum& whole,
                        const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  MinkowskiSum m;
  const SumParts P = SumParts::Planes;
  if ((diff ? minkowski_difference(SA, pa, SB, pb, m, P) : minkowski_sum(SA, pa, SB, pb, m, P)) != Status::Ok)
    fuzz::fail("the planes level failed where the whole sum did not");
  if (whole.corrected || m.parts == SumParts::Whole) return;  // (the corrector's answer is whole)
  if (m.F != whole.F || int(m.planes.size()) != m.F || !m.vertices.empty() || !m.loop_vertex.empty())
    fuzz::fail("the planes level has other facets than the whole sum");
  double size = 1;
  for (const auto* x : {&a, &b})
    for (const auto& p : *x) size = std::max(size, p.cwiseAbs().maxCoeff());
  const double sign = diff ? -1 : 1;
  for (int k = 0; k < m.F; ++k) {
    const SumPlane &p = m.planes[size_t(k)], &w = whole.planes[size_t(k)];
    if (p.normal != w.normal || !(std::abs(p.offset - w.offset) <= 1e-9 * size))
      fuzz::fail("a plane of the planes level is not the whole sum's");
    if (p.i < 0 || p.i >= int(a.size()) || p.j < 0 || p.j >= int(b.size()) ||
        !(std::abs(p.normal.dot(a[size_t(p.i)] + sign * b[size_t(p.j)]) - p.offset) <= 1e-9 * size))
      fuzz::fail("a plane's pair is not on it at the planes level");
  }
  // The vertices level: the whole sum less its loops, bit for bit.
  if ((diff ? minkowski_difference(SA, pa, SB, pb, m, SumParts::Vertices)
            : minkowski_sum(SA, pa, SB, pb, m, SumParts::Vertices)) != Status::Ok)
    fuzz::fail("the vertices level failed where the whole sum did not");
  const auto same_vertex = [](const SumVertex& x, const SumVertex& y) { return x.i == y.i && x.j == y.j && x.point == y.point; };
  if (m.parts != SumParts::Vertices || m.V != whole.V || m.E != whole.E || m.F != whole.F || !m.euler_ok ||
      !m.loop_start.empty() || !m.loop_vertex.empty() ||
      !std::equal(m.vertices.begin(), m.vertices.end(), whole.vertices.begin(), whole.vertices.end(), same_vertex) ||
      !std::equal(m.planes.begin(), m.planes.end(), whole.planes.begin(), whole.planes.end(),
                  [](const SumPlane& x, const SumPlane& y) {
                    return x.normal == y.normal && x.offset == y.offset && x.i == y.i && x.j == y.j;
                  }))
    fuzz::fail("the vertices level is not the whole sum less its loops");
}

// The small overlay's tables against the walks on the posed pair (placed as the sum places
// it): where the tables answer, the same cell for every normal and the same crossings.
void check_small_overlay(const ConvexShape& SA, const Eigen::Isometry3d& pa, const ConvexShape& SB,
                         const Eigen::Isometry3d& pb, bool diff) {
  const detail::ShapeData &da = *detail::ShapeAccess::data(SA), &db = *detail::ShapeAccess::data(SB);
  if (!detail::small_overlay_fits(da, db)) return;
  const Eigen::Matrix3d relative = pa.linear() == pb.linear() ? Eigen::Matrix3d::Identity()
                                                              : Eigen::Matrix3d(pa.linear().transpose() * pb.linear());
  detail::PlacedBuffers buffers[2][2];
  detail::Placed A[2], B[2];
  detail::Overlay overlay[2];  // [0] the walks, [1] the tables
  bool ok[2];
  for (int w = 0; w < 2; ++w) {
    detail::place(da, pa, Eigen::Matrix3d::Identity(), false, buffers[w][0], A[w]);
    detail::place(db, pb, relative, diff, buffers[w][1], B[w]);
    ok[w] = overlay[w].locate(A[w], B[w], w == 1);
  }
  if (!overlay[1].by_tables) return;
  if (!ok[0]) fuzz::fail("the walks failed where the small tables answered");
  const auto same = [](const std::vector<detail::Location>& x, const std::vector<detail::Location>& y) {
    return std::equal(x.begin(), x.end(), y.begin(), y.end(),
                      [](const auto& p, const auto& q) { return p.kind == q.kind && p.id == q.id; });
  };
  if (!same(overlay[0].a_normals(), overlay[1].a_normals()) || !same(overlay[0].b_normals(), overlay[1].b_normals()))
    fuzz::fail("the small tables located a normal elsewhere than the walks");
  std::set<std::tuple<int, int, bool>> crossings[2];
  for (int w = 0; w < 2; ++w)
    for (const auto& x : overlay[w].arc_crossings()) crossings[w].emplace(x.ea, x.eb, x.up);
  if (crossings[0] != crossings[1] || crossings[1].size() != overlay[1].arc_crossings().size())
    fuzz::fail("the small tables found other crossings than the walks");
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
// The exact structure certificate of grid mode and rounded mode, in a number type T that holds
// every pairwise sum exactly (long long on the grid, GMP rationals otherwise).
template <class T>
using Exact3 = std::array<T, 3>;

template <class T>
Exact3<T> minus(const Exact3<T>& p, const Exact3<T>& q) {
  return {p[0] - q[0], p[1] - q[1], p[2] - q[2]};
}
template <class T>
Exact3<T> cross(const Exact3<T>& p, const Exact3<T>& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}
template <class T>
T dot(const Exact3<T>& p, const Exact3<T>& q) {
  return p[0] * q[0] + p[1] * q[1] + p[2] * q[2];
}
template <class T>
bool is_zero(const Exact3<T>& p) {
  return p[0] == 0 && p[1] == 0 && p[2] == 0;
}

// Certifies that `fast` is the exact hull of the pairwise sums a_i + s b_j, from its output
// alone (no other path of the library): a closed surface (every directed edge of a loop has
// its twin, V - E + F = 2 counted from the loops), each vertex the exact sum its pair names,
// each facet's loop exactly coplanar with no three consecutive vertices collinear, every
// pairwise sum exactly on the inner side of every facet, and no two facets across an edge
// coplanar. A closed convex surface through points of the set that holds the whole set is its
// hull, with coplanar facets merged: an answer, not only a consistent one.
template <class T, class Convert>
void check_exact_structure(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, bool diff,
                           const MinkowskiSum& fast, Convert exact) {
  if (fast.corrected) fuzz::fail("the fast path needed the corrector on a tie input");
  const T sign = diff ? -1 : 1;
  const auto sum = [&](const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    const Exact3<T> x = exact(p), y = exact(q);
    return Exact3<T>{x[0] + sign * y[0], x[1] + sign * y[1], x[2] + sign * y[2]};
  };
  std::vector<Exact3<T>> sums;
  for (const auto& p : a)
    for (const auto& q : b) sums.push_back(sum(p, q));
  std::vector<Exact3<T>> vertex;
  for (const auto& v : fast.vertices) {
    if (v.i < 0 || v.i >= int(a.size()) || v.j < 0 || v.j >= int(b.size()))
      fuzz::fail("a vertex's pair (i, j) out of range");
    vertex.push_back(sums[size_t(v.i) * b.size() + size_t(v.j)]);
  }
  std::map<std::pair<int, int>, int> edges;  // directed loop edge -> its facet
  std::vector<Exact3<T>> normal(size_t(fast.F));
  for (int k = 0; k < fast.F; ++k) {
    const Loop loop = fast.facet(k);
    const int n = int(loop.size());
    Exact3<T> nk{0, 0, 0};  // a normal from the first corner
    for (int c = 0; c < n; ++c) {
      const Exact3<T>&p = vertex[size_t(loop[c])], &q = vertex[size_t(loop[(c + 1) % n])],
      &r = vertex[size_t(loop[(c + 2) % n])];
      const Exact3<T> turn = cross(minus(q, p), minus(r, q));
      if (is_zero(turn)) fuzz::fail("three consecutive vertices of a facet are collinear");
      if (is_zero(nk)) nk = turn;
      if (dot(turn, nk) <= 0) fuzz::fail("a facet's loop is not convex");
      if (!edges.emplace(std::pair{loop[c], loop[(c + 1) % n]}, k).second) fuzz::fail("a directed edge in two loops");
    }
    const Exact3<T>& o = vertex[size_t(loop[0])];
    for (int c = 0; c < n; ++c)
      if (dot(nk, minus(vertex[size_t(loop[c])], o)) != 0) fuzz::fail("a facet is not exactly planar");
    for (const Exact3<T>& x : sums)
      if (dot(nk, minus(x, o)) > 0) fuzz::fail("a pairwise sum lies outside a facet");
    normal[size_t(k)] = nk;
  }
  for (const auto& [e, k] : edges) {
    const auto twin = edges.find({e.second, e.first});
    if (twin == edges.end()) fuzz::fail("a sum's surface is not closed");
    if (is_zero(cross(normal[size_t(k)], normal[size_t(twin->second)]))) fuzz::fail("two coplanar facets not merged");
  }
  const long long E = static_cast<long long>(edges.size()) / 2;
  if (static_cast<long long>(fast.vertices.size()) - E + fast.F != 2 || fast.V != int(fast.vertices.size()) || fast.E != E)
    fuzz::fail("V - E + F is not 2, counted from the loops");
}

// Grid mode (flag 16): every coordinate snapped to the integers within +-r, r = 1 ... 8, where
// ties are the rule (parallel faces and edges, coplanar points): the structure certified in
// integers; every vertex an integer point. (a and b: the vertices the sum's pairs (i, j) index.)
void check_grid_structure(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, bool diff,
                          const MinkowskiSum& fast) {
  for (const auto& v : fast.vertices)
    if (v.point != v.point.array().round().matrix()) fuzz::fail("a grid sum's vertex is not an integer point");
  check_exact_structure<long long>(a, b, diff, fast, [](const Eigen::Vector3d& v) {
    return Exact3<long long>{std::llround(v.x()), std::llround(v.y()), std::llround(v.z())};
  });
}

// Rounded mode (flag 32): cos/sin prisms of 3 to 12 sides (A's; B's the same polygon, halved,
// of another radius, or turned about the shared axis) or a box turned about z, from the input:
// ties whose faces' exact normals are not doubles. The structure certified in rationals.
void check_rounded_structure(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, bool diff,
                             const MinkowskiSum& fast) {
  check_exact_structure<mpq_class>(a, b, diff, fast, [](const Eigen::Vector3d& v) {
    return Exact3<mpq_class>{mpq_class(v.x()), mpq_class(v.y()), mpq_class(v.z())};
  });
}

// An n-gon prism of radius r between heights z0 and z1, turned by `phase` (rad).
std::vector<Eigen::Vector3d> prism(int n, double r, double z0, double z1, double phase) {
  std::vector<Eigen::Vector3d> p;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * M_PI * k / n + phase;
    p.emplace_back(r * std::cos(t), r * std::sin(t), z0), p.emplace_back(r * std::cos(t), r * std::sin(t), z1);
  }
  return p;
}

// The rounded-mode operands from the input (sizes in (0, 4], angles in [0, 2 pi)).
void rounded_operands(fuzz::Bytes& in, std::vector<Eigen::Vector3d>& a, std::vector<Eigen::Vector3d>& b) {
  const auto size = [&] { return (1 + in.take<uint16_t>()) / 16384.0; };
  const auto angle = [&] { return in.take<uint16_t>() * (2 * M_PI / 65536); };
  const int n = 3 + in.take<uint8_t>() % 10, m = 3 + in.take<uint8_t>() % 10, kind = in.take<uint8_t>() % 5;
  const double r = size(), phase = angle();
  a = prism(n, r, -size(), size(), phase);
  if (kind == 0) b = prism(n, r, -size(), size(), phase);        // the same polygon
  if (kind == 1) b = prism(n, r / 2, -size(), size(), phase);    // halved: parallel sides
  if (kind == 2) b = prism(n, size(), -size(), size(), phase);   // another radius: slivers
  if (kind == 3) b = prism(m, size(), -size(), size(), angle()); // turned about the axis
  if (kind == 4) {  // boxes turned about z
    const double c = std::cos(phase), s = std::sin(phase), h[3] = {size(), size(), size()};
    a.clear(), b = prism(4, size(), -size(), size(), angle());
    for (int k = 0; k < 8; ++k) {
      const double x = k & 1 ? h[0] : -h[0], y = k & 2 ? h[1] : -h[1];
      a.emplace_back(c * x - s * y, s * x + c * y, k & 4 ? h[2] : -h[2]);
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
  const bool grid = flags & 16, rounded = !grid && (flags & 32);
  const double r = grid ? 1 + in.take<uint8_t>() % 8 : 0;
  const auto coordinate = [&] {
    const double x = in.number();
    return grid ? std::fmod(std::abs(std::isfinite(x) ? std::round(x) : 0.0), 2 * r + 1) - r : x;
  };
  std::vector<Eigen::Vector3d> a, b;
  if (rounded) {
    rounded_operands(in, a, b);
  } else {
    for (int k = 0; k < na; ++k) a.emplace_back(coordinate(), coordinate(), coordinate());
    for (int k = 0; k < nb; ++k) b.emplace_back(coordinate(), coordinate(), coordinate());
  }
  ConvexPolytope A, B;
  if (polytope_from_points(a, A) != Status::Ok || polytope_from_points(b, B) != Status::Ok) return 0;
  Proximity prox;
  double reach = 0;  // (the operands' largest coordinate: the scale of the witnesses' rounding)
  for (const auto* p : {&A.vertices, &B.vertices})
    for (const auto& v : *p) reach = std::max(reach, v.cwiseAbs().maxCoeff());
  if (proximity(A, B, prox) == Status::Ok) fuzz::check(prox, reach);
  const Method method = grid || rounded || flags % 3 == 0 ? Method::Fast : flags % 3 == 1 ? Method::Reference : Method::Hull;
  const bool diff = flags & 4;
  MinkowskiSum m;
  const Status s = diff ? minkowski_difference(A, B, m, method) : minkowski_sum(A, B, m, method);
  if (s != Status::Ok) return 0;  // a status is a clear answer (e.g. DegenerateResult)
  check_planes(m, A.vertices, B.vertices, diff ? -1 : 1);
  if (grid) check_grid_structure(A.vertices, B.vertices, diff, m);
  if (rounded) check_rounded_structure(A.vertices, B.vertices, diff, m);
  const MinkowskiSum unposed = m;
  // The same operands as prepared shapes under poses read from the rest of the input (a unit
  // quaternion and a translation each; with flag 8, a raw 3x3 matrix for B: rarely a rotation;
  // in grid mode signed permutations and integer translations, which keep every tie exact).
  ConvexShape SA, SB;
  if (shape_from_points(a, SA) != Status::Ok || shape_from_points(b, SB) != Status::Ok) return 0;  // a clear status
  const Eigen::Isometry3d pa = grid ? grid_pose(in) : pose(in, false);
  Eigen::Isometry3d pb = grid ? grid_pose(in) : pose(in, flags & 8 && !rounded);
  if (rounded) pb.linear() = pa.linear();  // (one rotation: the ties stay, in A's body frame)
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
  check_levels(SA, pa, SB, pb, diff, m, wa, wb);
  check_small_overlay(SA, pa, SB, pb, diff);
  // Under one rotation the structure is the unposed sum's, pair for pair (shape_from_points
  // numbers the vertices as polytope_from_points does).
  if (rounded && (m.V != unposed.V || m.F != unposed.F || m.loop_vertex.size() != unposed.loop_vertex.size()))
    fuzz::fail("a rounded sum under one rotation lost its structure");
  if (grid) {
    ConvexPolytope WA, WB;
    if (polytope_from_points(wa, WA) != Status::Ok || polytope_from_points(wb, WB) != Status::Ok)
      fuzz::fail("a moved grid operand is no longer a polytope");
    check_grid_structure(wa, wb, diff, m);
  }
  return 0;
}
