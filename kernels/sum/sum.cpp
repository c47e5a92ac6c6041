// The public Minkowski sum and difference: validation, then the overlay, the kernel or the reference path.
#include <algorithm>
#include <cmath>
#include <limits>

#include <minksum/kernels.hpp>

#include "core/hull.hpp"
#include "sum/overlay.hpp"
#include "sum/sum_internal.hpp"

namespace minksum {

using Eigen::Vector3d;

namespace detail {

namespace {

// The vertices of a placed operand, as points (for the corrector).
std::vector<Vector3d> points(const Placed& x) {
  std::vector<Vector3d> p(x.s->px.size());
  for (size_t k = 0; k < p.size(); ++k) p[k] = x.point(int(k));
  return p;
}

}  // namespace

// The overlay of two prepared shapes placed by their poses (B negated for a difference), or
// the corrector when a step of it fails.
Status sum_placed(const ShapeData& a, const Eigen::Isometry3d& pose_a, const ShapeData& b,
                  const Eigen::Isometry3d& pose_b, bool difference, MinkowskiSum& out, SumParts parts) {
  // Two coplanar flat operands have a flat sum; the result type describes solids only.
  if (a.polytope_ref->flat && b.polytope_ref->flat &&
      (pose_a.linear() * a.polytope_ref->faces[0].normal)
              .cross(pose_b.linear() * b.polytope_ref->faces[0].normal)
              .norm() <= 1e-12)
    return out = MinkowskiSum{}, Status::DegenerateResult;
  thread_local PlacedBuffers buffer_a, buffer_b;
  thread_local Overlay scratch;
  Placed A, B;
  // The overlay in A's body frame: B turned by R_A^T R_B, exactly the identity under one rotation.
  const Eigen::Matrix3d relative = pose_a.linear() == pose_b.linear()
                                       ? Eigen::Matrix3d::Identity()
                                       : Eigen::Matrix3d(pose_a.linear().transpose() * pose_b.linear());
  place(a, pose_a, Eigen::Matrix3d::Identity(), false, buffer_a, A);
  place(b, pose_b, relative, difference, buffer_b, B);
  // A map whose rounding can misplace a normal by more than 1e-10 of the size in support
  // (ShapeData::support_error: slivers; random polytopes of 2048 points reach 3e-11) has its
  // result certified by the support check (O(output)).
  const bool certify = a.support_error + b.support_error > 1e-10 * std::max(a.size, b.size);
  if (scratch.run(A, B, out, parts) && (!certify || planes_support(A, B, out))) {
    // The vertices level is the whole one without its loops, which certified it (Euler's
    // relation, the support check) and are dropped only now.
    if (parts == SumParts::Vertices) out.loop_start.clear(), out.loop_vertex.clear(), out.parts = SumParts::Vertices;
    return Status::Ok;
  }
  // Section 3 of the paper: an inconsistent result is rebuilt from the hull (whole).
  const Status s = hull_corrector(points(A), points(B), out);
  out.method = Method::Fast, out.parts = SumParts::Whole;
  return s;
}

}  // namespace detail

namespace {

bool usable(const ConvexPolytope& p) { return p.vertices.size() >= 3 && p.faces.size() >= 2 && !p.edges.empty(); }

// -B: vertices and normals negated; loops reversed so they stay counter-clockwise from outside.
ConvexPolytope negated(const ConvexPolytope& p) {
  ConvexPolytope n = p;
  for (auto& v : n.vertices) v = -v;
  for (auto& f : n.faces) {
    f.normal = -f.normal;
    std::reverse(f.loop.begin(), f.loop.end());
  }
  for (auto& e : n.edges) std::swap(e.left, e.right);
  return n;
}

std::vector<Vector3d> signed_points(const ConvexPolytope& p, bool negate) {
  std::vector<Vector3d> v = p.vertices;
  if (negate)
    for (auto& x : v) x = -x;
  return v;
}

Status sum_dispatch(const ConvexPolytope& a, const ConvexPolytope& b, bool difference, MinkowskiSum& out,
                    Method method) {
  if (method == Method::Kernel) method = Method::Fast;  // the kernel takes two boxes
  // An error leaves an empty result; a result reuses the capacity of `out`.
  const auto fail = [&out](Status s) {
    out = MinkowskiSum{};
    return s;
  };
  out.method = method, out.corrected = false, out.parts = SumParts::Whole;
  if (!usable(a) || !usable(b)) return fail(Status::TooFewPoints);
  // Two coplanar flat operands have a flat sum; the result type describes solids only.
  if (a.flat && b.flat && a.faces[0].normal.cross(b.faces[0].normal).norm() <= 1e-12)
    return fail(Status::DegenerateResult);
  const auto corrector = [&] {
    const Status s = detail::hull_corrector(a.vertices, signed_points(b, difference), out);
    out.method = method;
    return s;
  };
  if (method == Method::Hull) {
    const Status s = corrector();
    out.corrected = false;  // the hull is the method here, not a correction
    return s;
  }
  // Both are prepared as a ConvexShape would be (per thread, reusing the capacity); one that
  // breaks the polytope contract gets the corrector's answer, from its vertices alone.
  thread_local detail::ShapeData prepared_a, prepared_b;
  if (detail::prepare(a, prepared_a, false) != Status::Ok || detail::prepare(b, prepared_b, difference) != Status::Ok)
    return corrector();
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  if (method == Method::Fast)
    return detail::sum_placed(prepared_a, identity, prepared_b, identity, difference, out, SumParts::Whole);
  detail::sum_reference(a, difference ? negated(b) : b, out);
  // Section 3 of the paper: an inconsistent result (Euler fails, or a plane that does not
  // support the sum) is rebuilt from the hull.
  thread_local detail::PlacedBuffers buffer_a, buffer_b;
  detail::Placed A, B;
  detail::place(prepared_a, identity, identity.linear(), false, buffer_a, A);
  detail::place(prepared_b, identity, identity.linear(), difference, buffer_b, B);
  if (!out.euler_ok || !detail::planes_support(A, B, out)) return corrector();
  return Status::Ok;
}

// The sum of a point core p (A, or B with `point_is_b`) and a solid core q placed by its pose:
// q translated by p, or for a difference p - q or q - p (q negated: its normals, and its loops
// reversed to stay counter-clockwise from outside). The pairs index q's vertices and the
// point's one vertex (0); each plane's offset is the highest of its face's placed vertices along it.
void point_sum(const Vector3d& p, const ConvexPolytope& q, const Eigen::Isometry3d& pose, bool point_is_b,
               bool difference, MinkowskiSum& out) {
  // (Cleared, not replaced: a reused result keeps its capacity.)
  out.planes.clear(), out.loop_start.clear(), out.loop_vertex.clear(), out.vertices.clear();
  out.corrected = false, out.method = Method::Fast, out.parts = SumParts::Whole, out.radius = 0;
  const double sign = difference && !point_is_b ? -1.0 : 1.0, shift = difference && point_is_b ? -1.0 : 1.0;
  const int V = int(q.vertices.size());
  out.vertices.reserve(size_t(V)), out.planes.reserve(q.faces.size()), out.loop_start.reserve(q.faces.size() + 1);
  for (int k = 0; k < V; ++k) {
    SumVertex v;
    v.i = point_is_b ? k : 0, v.j = point_is_b ? 0 : k;
    v.point = sign * (pose * q.vertices[size_t(k)]) + shift * p;
    out.vertices.push_back(v);
  }
  out.loop_start.push_back(0);
  for (const Face& f : q.faces) {
    SumPlane plane;
    plane.normal = sign * (pose.linear() * f.normal);
    plane.offset = -std::numeric_limits<double>::infinity();
    for (int k : f.loop) plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[size_t(k)].point));
    // The loop from its smallest vertex, reversed for a negated q.
    const int n = int(f.loop.size());
    const int least = int(std::min_element(f.loop.begin(), f.loop.end()) - f.loop.begin());
    for (int k = 0; k < n; ++k) out.loop_vertex.push_back(f.loop[size_t((least + (sign > 0 ? k : n - k)) % n)]);
    plane.i = out.vertices[size_t(out.loop_vertex[size_t(out.loop_start.back())])].i;
    plane.j = out.vertices[size_t(out.loop_vertex[size_t(out.loop_start.back())])].j;
    out.planes.push_back(plane);
    out.loop_start.push_back(int(out.loop_vertex.size()));
  }
  out.V = V, out.F = int(q.faces.size()), out.E = int(q.edges.size());
  out.euler_ok = out.V - out.E + out.F == 2;
}

// The dimension of a posed sum of cores (3: a solid), for a point (0), a segment (1), a flat
// polygon (2) or a solid (3): the sum of two points is a point; a point and a segment, or two
// parallel segments, a segment; two segments, a point and a polygon, a segment in a polygon's
// plane or two coplanar polygons, a polygon; `normal` is then its plane's. Parallel to 1e-12.
int sum_dimension(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                  const Eigen::Isometry3d& pose_b, Vector3d& normal) {
  using Kind = detail::ShapeData::Kind;
  const auto dims = [](const ConvexShape& s) {
    const detail::ShapeData* d = detail::ShapeAccess::data(s);
    return d->kind == Kind::Point ? 0 : d->kind == Kind::Segment ? 1 : d->polytope_ref->flat ? 2 : 3;
  };
  const int na = dims(a), nb = dims(b);
  if (na == 3 || nb == 3) return 3;  // (the common case first: a solid core)
  if (na + nb < 2) return std::max(na, nb);
  const auto axis = [](const Eigen::Isometry3d& pose) { return Vector3d(pose.linear() * Vector3d::UnitZ()); };
  const auto plane = [](const ConvexShape& s, const Eigen::Isometry3d& pose) {
    return Vector3d(pose.linear() * s.polytope().faces[0].normal);
  };
  if (na == 1 && nb == 1) {  // (a capsule's segment runs along its z)
    const Vector3d c = axis(pose_a).cross(axis(pose_b));
    if (c.norm() <= 1e-12) return 1;
    return normal = c.normalized(), 2;
  }
  if (na + nb == 1) return 1;
  if (na == 2 && nb == 2) {
    normal = plane(a, pose_a);
    return normal.cross(plane(b, pose_b)).norm() <= 1e-12 ? 2 : 3;
  }
  if (na == 1 || nb == 1) {
    normal = na == 2 ? plane(a, pose_a) : plane(b, pose_b);
    return std::abs(axis(na == 1 ? pose_a : pose_b).dot(normal)) > 1e-12 ? 3 : 2;
  }
  return normal = na == 2 ? plane(a, pose_a) : plane(b, pose_b), 2;  // a point and a polygon
}

// A rounded sum whose cores sum to a point, a segment or a polygon (dimension `dims`; a
// polygon's plane `normal`): swept by the radii it is a solid. Its core is the hull of the
// pairwise sums in their line or plane: a point (V 1, no edges, no facets), a segment (V 2,
// E 1, no facets) or a polygon with its two sides (V = E, F 2), as a flat polytope has them.
void low_sum(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
             const Eigen::Isometry3d& pose_b, bool difference, int dims, const Vector3d& normal, MinkowskiSum& out) {
  out.planes.clear(), out.loop_start.clear(), out.loop_vertex.clear(), out.vertices.clear();
  out.corrected = false, out.method = Method::Fast, out.parts = SumParts::Whole, out.euler_ok = true;
  const std::vector<Vector3d> &va = a.polytope().vertices, &vb = b.polytope().vertices;
  std::vector<Vector3d> sums;
  std::vector<std::pair<int, int>> pair;
  for (size_t i = 0; i < va.size(); ++i)
    for (size_t j = 0; j < vb.size(); ++j) {
      const Vector3d q = pose_b * vb[j];
      sums.push_back(pose_a * va[i] + (difference ? Vector3d(-q) : q));
      pair.emplace_back(int(i), int(j));
    }
  std::vector<int> corners;  // into sums: the point, the segment's ends, the polygon counter-clockwise
  if (dims == 0) {
    corners = {0};
  } else if (dims == 1) {  // the extremes along the line (two points of it that differ)
    Vector3d d = Vector3d::Zero();
    for (const Vector3d& q : sums)
      if ((q - sums.front()).squaredNorm() > d.squaredNorm()) d = q - sums.front();
    int lo = 0, hi = 0;
    for (int k = 1; k < int(sums.size()); ++k) {
      if (d.dot(sums[size_t(k)]) < d.dot(sums[size_t(lo)])) lo = k;
      if (d.dot(sums[size_t(k)]) > d.dot(sums[size_t(hi)])) hi = k;
    }
    corners = lo == hi ? std::vector<int>{lo} : std::vector<int>{lo, hi};
  } else {
    std::vector<int> all(sums.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = int(k);
    corners = detail::planar_hull(sums, all, normal);
  }
  // The vertices sorted by their pairs, as every sum's are.
  std::vector<int> order = corners;
  std::sort(order.begin(), order.end(), [&](int x, int y) { return pair[size_t(x)] < pair[size_t(y)]; });
  std::vector<int> number(sums.size(), -1);
  for (int k : order) {
    number[size_t(k)] = int(out.vertices.size());
    out.vertices.push_back(SumVertex{pair[size_t(k)].first, pair[size_t(k)].second, sums[size_t(k)]});
  }
  out.V = int(out.vertices.size()), out.E = out.V < 3 ? out.V - 1 : out.V, out.F = 0;
  out.loop_start.push_back(0);
  if (out.V < 3) return;
  for (const double side : {1.0, -1.0}) {  // the top side counter-clockwise about normal, the bottom reversed
    std::vector<int> loop;
    for (int k : corners) loop.push_back(number[size_t(k)]);
    if (side < 0) std::reverse(loop.begin(), loop.end());
    std::rotate(loop.begin(), std::min_element(loop.begin(), loop.end()), loop.end());
    SumPlane plane;
    plane.normal = side * normal;
    plane.offset = -std::numeric_limits<double>::infinity();
    for (int v : loop) plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[size_t(v)].point));
    plane.i = out.vertices[size_t(loop[0])].i, plane.j = out.vertices[size_t(loop[0])].j;
    out.planes.push_back(plane);
    out.loop_vertex.insert(out.loop_vertex.end(), loop.begin(), loop.end());
    out.loop_start.push_back(int(out.loop_vertex.size()));
  }
  out.F = 2;
}

// The sum of a segment core and another core (not a point): the hull of the pairwise sums of
// their vertices (the exact hull, core/hull.hpp, with index tracking: the segment's two ends against every vertex),
// whole; the overlay reads Gauss maps, which a segment has not.
Status segment_sum(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                   const Eigen::Isometry3d& pose_b, bool difference, MinkowskiSum& out) {
  std::vector<Vector3d> pa, pb;
  for (const Vector3d& v : a.polytope().vertices) pa.push_back(pose_a * v);
  for (const Vector3d& v : b.polytope().vertices) pb.push_back(difference ? Vector3d(-(pose_b * v)) : Vector3d(pose_b * v));
  const Status s = detail::hull_corrector(pa, pb, out);
  out.method = Method::Hull, out.corrected = false, out.parts = SumParts::Whole;
  return s;
}

// Checks the shapes and poses of a posed sum. Rounded shapes: the sum of the cores, whole
// (reading it with the radius needs the loops), with the radii added; a point core and a solid
// one: the solid translated; a segment core: the hull of the pairwise sums; cores that sum to
// less than a solid: low_sum. Polytopes whose sum is not a solid: DegenerateResult.
Status sum_shapes(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                  const Eigen::Isometry3d& pose_b, bool difference, MinkowskiSum& out, SumParts parts) {
  const detail::ShapeData *da = detail::ShapeAccess::data(a), *db = detail::ShapeAccess::data(b);
  Status s = !da || !db ? Status::TooFewPoints : check_pose(pose_a);
  if (s == Status::Ok) s = check_pose(pose_b);
  if (s != Status::Ok) return out = MinkowskiSum{}, s;
  const double radius = a.radius() + b.radius();
  Vector3d normal = Vector3d::Zero();
  const int dims = sum_dimension(a, pose_a, b, pose_b, normal);
  if (dims < 3 && !(radius > 0)) return out = MinkowskiSum{}, Status::DegenerateResult;
  if (radius > 0) parts = SumParts::Whole;
  using Kind = detail::ShapeData::Kind;
  if (dims < 3)
    low_sum(a, pose_a, b, pose_b, difference, dims, normal, out);
  else if (da->kind == Kind::Point)
    point_sum(pose_a * a.polytope().vertices.front(), b.polytope(), pose_b, false, difference, out);
  else if (db->kind == Kind::Point)
    point_sum(pose_b * b.polytope().vertices.front(), a.polytope(), pose_a, true, difference, out);
  else if (da->kind == Kind::Segment || db->kind == Kind::Segment)
    s = segment_sum(a, pose_a, b, pose_b, difference, out);
  else
    s = detail::sum_placed(*da, pose_a, *db, pose_b, difference, out, parts);
  if (s == Status::Ok) out.radius = radius;
  return s;
}

}  // namespace

Status minkowski_sum(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out, Method method) {
  return sum_dispatch(a, b, false, out, method);
}

Status minkowski_difference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out, Method method) {
  return sum_dispatch(a, b, true, out, method);
}

Status minkowski_sum(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                     const Eigen::Isometry3d& pose_b, MinkowskiSum& out, SumParts parts) {
  return sum_shapes(a, pose_a, b, pose_b, false, out, parts);
}

Status minkowski_difference(const ConvexShape& a, const Eigen::Isometry3d& pose_a, const ConvexShape& b,
                            const Eigen::Isometry3d& pose_b, MinkowskiSum& out, SumParts parts) {
  return sum_shapes(a, pose_a, b, pose_b, true, out, parts);
}

Status minkowski_sum(const Box& a, const Box& b, MinkowskiSum& out) {
  for (const Box* x : {&a, &b})
    if (const Status s = check_box(*x); s != Status::Ok) {
      out = MinkowskiSum{};
      return s;
    }
  // The kernel's whole-polytope path on one lane: 30 planes and their vertex loops (symmetry
  // and index tracking; see box_box_sum), its buffers on the stack (about 26 KB).
  BoxBatch<double, kLaneMultiple> A, B;
  BoxBoxSum<double, kLaneMultiple> sum;
  A.set_one(a), B.set_one(b);
  box_box_sum(A, B, sum);
  // The 32 vertices: the pairs the loops visit, numbered in (i, j) order (bit 8 i + j).
  std::uint64_t used = 0;
  for (int p = 0; p < 30; ++p)
    for (int m = 0; m < 4; ++m) {
      const int v = int(sum.loop[p][0] >> (6 * m) & 63);
      used |= std::uint64_t(1) << (8 * (v & 7) + (v >> 3));
    }
  // Out of general position (parallel edges, three coplanar ones) facets merge, and the loops
  // are not meaningful: the general path.
  if (!sum.general[0] || __builtin_popcountll(used) != 32) {
    thread_local ConvexPolytope pa, pb;  // vertex k is box_corner(k), as the kernel's codes number them
    polytope_from_box(a, pa), polytope_from_box(b, pb);
    return minkowski_sum(pa, pb, out, Method::Fast);
  }
  int number[64];
  out.vertices.resize(32);
  Vector3d corner_a[8], corner_b[8];
  for (int k = 0; k < 8; ++k) corner_a[k] = box_corner(a, k), corner_b[k] = box_corner(b, k);
  int v = 0;
  for (std::uint64_t m = used; m; m &= m - 1, ++v) {
    const int bit = __builtin_ctzll(m), i = bit >> 3, j = bit & 7;
    number[bit] = v;
    out.vertices[v] = SumVertex{i, j, corner_a[i] + corner_b[j]};
  }
  // Facet p < 15 has axis p's plane, p + 15 the opposite one; each loop starts at its smallest
  // pair (the support corners with the facet's edge bits clear), as assemble's do, and the
  // plane's pair is that one; the offsets are the kernel's support function h_A(n) + h_B(n).
  out.planes.resize(30), out.loop_start.resize(31), out.loop_vertex.resize(120);
  for (int p = 0; p < 30; ++p) {
    const int q = p % 15;
    int* loop = &out.loop_vertex[size_t(4 * p)];
    out.loop_start[p] = 4 * p;
    for (int m = 0; m < 4; ++m) {
      const int code = int(sum.loop[p][0] >> (6 * m) & 63);
      loop[m] = number[8 * (code & 7) + (code >> 3)];
    }
    SumPlane& plane = out.planes[p];
    plane.normal =
        (p < 15 ? 1.0 : -1.0) * Vector3d(sum.planes.n[q][0][0], sum.planes.n[q][1][0], sum.planes.n[q][2][0]);
    plane.offset = sum.planes.offset[p][0];
    plane.i = out.vertices[loop[0]].i, plane.j = out.vertices[loop[0]].j;
  }
  out.loop_start[30] = 120;
  out.V = 32, out.E = 60, out.F = 30;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Kernel, out.parts = SumParts::Whole;
  return Status::Ok;
}

}  // namespace minksum
