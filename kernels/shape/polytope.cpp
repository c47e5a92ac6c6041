// Building and validating convex polytopes (boxes, triangles, point sets, explicit meshes).
#include <minksum/model.hpp>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/hull.hpp"
#include "core/manifold.hpp"
#include "core/predicates.hpp"
#include "core/scale.hpp"
#include "core/validate.hpp"

namespace minksum {

using detail::kFlatTol;
using detail::kLineTol;
using Eigen::Vector3d;

namespace {

Status check_coordinates(const std::vector<Vector3d>& pts) { return detail::check_coordinates(pts.data(), pts.size()); }
double diagonal(const std::vector<Vector3d>& pts) { return detail::diagonal(pts.data(), pts.size()); }

// Fills `edges` from the face loops (in (v0, v1) order); false unless every directed edge has
// exactly one twin.
bool edges_from_loops(ConvexPolytope& p) {
  std::vector<int> start(1, 0), vertex, face, twin, scratch;
  for (int f = 0; f < int(p.faces.size()); ++f) {
    for (int v : p.faces[f].loop) vertex.push_back(v), face.push_back(f);
    start.push_back(int(vertex.size()));
  }
  twin.resize(vertex.size());
  if (!detail::pair_edges(start.data(), int(p.faces.size()), vertex.data(), int(p.vertices.size()), twin.data(),
                          scratch))
    return false;
  p.edges.clear();
  for (size_t k = 0; k < vertex.size(); ++k) {
    const int v0 = vertex[k], v1 = vertex[size_t(twin[k])];  // the twin starts where this edge ends
    if (v0 < v1) p.edges.push_back(Edge{v0, v1, face[k], face[size_t(twin[k])]});
  }
  std::sort(p.edges.begin(), p.edges.end(),
            [](const Edge& x, const Edge& y) { return x.v0 != y.v0 ? x.v0 < y.v0 : x.v1 < y.v1; });
  return true;
}

// Flat polytope from a counter-clockwise (about n) loop of the points `pts`.
Status make_flat(const std::vector<Vector3d>& pts, const std::vector<int>& loop_ids, const Vector3d& n,
                 ConvexPolytope& out) {
  out = ConvexPolytope{};
  out.flat = true;
  std::vector<int> top;
  for (int id : loop_ids) {
    top.push_back(int(out.vertices.size()));
    out.vertices.push_back(pts[id]);
    out.input_index.push_back(id);
  }
  std::vector<int> bottom(top.rbegin(), top.rend());
  const double d = n.dot(out.vertices[0]);
  out.faces.push_back(Face{top, n, d});
  out.faces.push_back(Face{bottom, -n, -d});
  return edges_from_loops(out) ? Status::Ok : Status::InvalidMesh;
}

}  // namespace

Status polytope_from_points(const std::vector<Vector3d>& points, ConvexPolytope& out) {
  out = ConvexPolytope{};
  if (const Status s = check_coordinates(points); s != Status::Ok) return s;
  // Exact duplicates are dropped, keeping the first index.
  std::vector<int> order(points.size());
  for (int k = 0; k < int(points.size()); ++k) order[k] = k;
  auto lex = [&](int a, int b) {
    return std::lexicographical_compare(points[a].data(), points[a].data() + 3, points[b].data(), points[b].data() + 3);
  };
  std::stable_sort(order.begin(), order.end(), lex);
  std::vector<int> unique_ids;
  for (size_t k = 0; k < order.size(); ++k)
    if (k == 0 || points[order[k]] != points[order[k - 1]]) unique_ids.push_back(order[k]);
  std::sort(unique_ids.begin(), unique_ids.end());
  if (unique_ids.size() < 3) return Status::TooFewPoints;

  std::vector<Vector3d> pts;
  for (int id : unique_ids) pts.push_back(points[id]);
  const double extent = diagonal(pts);
  if (!(extent >= kMinExtent)) return Status::OutOfRange;  // (1e-200 across: every cross product is 0)
  // The shape tests see the points scaled by a power of two to about 1 across (exact), so that
  // their tolerances are relative.
  const double unit = detail::scale_to_one(extent), D = unit * extent;
  std::vector<Vector3d> scaled;
  for (const Vector3d& p : pts) scaled.push_back(unit * p);
  // Two far-apart points, then the point farthest from their line, then from their plane.
  auto farthest = [&](auto dist) {
    int best = 0;
    for (int k = 1; k < int(scaled.size()); ++k)
      if (dist(scaled[k]) > dist(scaled[best])) best = k;
    return best;
  };
  const int p1 = farthest([&](const Vector3d& p) { return (p - scaled[0]).squaredNorm(); });
  const Vector3d axis = (scaled[p1] - scaled[0]).normalized();
  auto line_dist = [&](const Vector3d& p) { return (p - scaled[0]).cross(axis).norm(); };
  const int p2 = farthest(line_dist);
  if (line_dist(scaled[p2]) <= kLineTol * D) return Status::Collinear;
  const Vector3d n = axis.cross(scaled[p2] - scaled[0]).normalized();
  auto plane_dist = [&](const Vector3d& p) { return std::abs(n.dot(p - scaled[0])); };
  // Flat within 64 eps of the size: flattening moves no corner farther than the queries' own
  // rounding tolerance (64 eps of the reach). Farther off, the exact hull keeps a thin solid (a
  // pentagon 900 off its plane at 8.5e12, flattened to 1e-10, put queries' witnesses 200 away),
  // unless it finds the points exactly coplanar (their plane read in doubles can be farther).
  detail::HullFacets hull;
  if (plane_dist(scaled[farthest(plane_dist)]) <= kFlatTol * D || !detail::convex_hull(scaled, hull)) {
    std::vector<int> all(scaled.size());
    for (int k = 0; k < int(scaled.size()); ++k) all[k] = k;
    std::vector<int> loop = detail::planar_hull(scaled, all, n);
    if (loop.size() < 3) return Status::Collinear;
    // The polygon's own normal (its loop's exact Newell normal, rounded), not n: n leans on
    // three of the points, and is rounded.
    const Vector3d newell = detail::exact_newell(scaled, loop);
    const Vector3d normal = newell.dot(n) > 0 ? Vector3d(newell.normalized()) : n;
    for (int& id : loop) id = unique_ids[id];
    return make_flat(points, loop, normal, out);
  }
  std::vector<int> remap(pts.size(), -1);  // index into pts -> vertex index, in input order
  for (int id : hull.index) remap[size_t(id)] = 0;
  for (size_t id = 0; id < pts.size(); ++id)
    if (remap[id] == 0) {
      remap[id] = int(out.vertices.size());
      out.vertices.push_back(pts[id]);
      out.input_index.push_back(unique_ids[id]);
    }
  for (int f = 0; f < hull.count(); ++f) {
    // (The exact Newell normal: it depends on the face alone, so exactly parallel faces stay
    // exactly parallel.)
    const Vector3d& n = hull.normal[size_t(f)];
    Face face{{}, n, -std::numeric_limits<double>::infinity()};
    for (int k = hull.start[size_t(f)]; k < hull.start[size_t(f) + 1]; ++k) {
      const int id = hull.index[size_t(k)];
      face.loop.push_back(remap[size_t(id)]);
      face.offset = std::max(face.offset, n.dot(pts[size_t(id)]));
    }
    out.faces.push_back(std::move(face));
  }
  return edges_from_loops(out) ? Status::Ok : Status::HullFailed;
}

Status polytope_from_mesh(const std::vector<Vector3d>& vertices, const std::vector<std::vector<int>>& faces,
                          ConvexPolytope& out) {
  out = ConvexPolytope{};
  if (const Status s = check_coordinates(vertices); s != Status::Ok) return s;
  if (vertices.size() < 4 || faces.size() < 4) return Status::InvalidMesh;
  const double D = diagonal(vertices);
  if (!(D >= kMinExtent)) return Status::OutOfRange;  // (its normals would underflow to zero)
  const double tol = 1e-9 * D;
  std::vector<bool> used(vertices.size(), false);
  Vector3d centroid = Vector3d::Zero();
  for (const auto& v : vertices) centroid += v;
  centroid /= double(vertices.size());

  ConvexPolytope mesh;
  mesh.vertices = vertices;
  for (const auto& loop : faces) {
    if (loop.size() < 3) return Status::InvalidMesh;
    for (int v : loop) {
      if (v < 0 || v >= int(vertices.size())) return Status::InvalidMesh;
      used[v] = true;
    }
    // Newell's method gives a robust normal for any planar polygon.
    Vector3d n = Vector3d::Zero();
    for (size_t k = 0; k < loop.size(); ++k) n += vertices[loop[k]].cross(vertices[loop[(k + 1) % loop.size()]]);
    if (n.norm() <= 1e-12 * D * D) return Status::InvalidMesh;
    n.normalize();
    Face f{loop, n, n.dot(vertices[loop[0]])};
    if (f.offset < n.dot(centroid)) {  // inward: flip to the outward orientation
      std::reverse(f.loop.begin(), f.loop.end());
      f.normal = -n;
      f.offset = -f.offset;
    }
    for (int v : f.loop)
      if (std::abs(f.normal.dot(vertices[v]) - f.offset) > tol) return Status::NotConvex;
    for (const auto& v : vertices)
      if (f.normal.dot(v) > f.offset + tol) return Status::NotConvex;
    // Each face must itself be a convex polygon: every turn is counter-clockwise about n.
    for (size_t k = 0; k < f.loop.size(); ++k) {
      const Vector3d& p0 = vertices[f.loop[k]];
      const Vector3d& p1 = vertices[f.loop[(k + 1) % f.loop.size()]];
      const Vector3d& p2 = vertices[f.loop[(k + 2) % f.loop.size()]];
      if ((p1 - p0).cross(p2 - p1).dot(f.normal) < -tol * D) return Status::NotConvex;
    }
    mesh.faces.push_back(std::move(f));
  }
  if (std::find(used.begin(), used.end(), false) != used.end()) return Status::InvalidMesh;
  if (!edges_from_loops(mesh)) return Status::InvalidMesh;
  const long euler = long(vertices.size()) - long(mesh.edges.size()) + long(mesh.faces.size());
  if (euler != 2) return Status::InvalidMesh;
  // Valid and convex: the canonical structure (coplanar faces merged) comes from the hull.
  return polytope_from_points(vertices, out);
}

Status polytope_from_box(const Box& box, ConvexPolytope& out) {
  if (const Status s = check_box(box); s != Status::Ok) {
    out = ConvexPolytope{};
    return s;
  }
  // Filled in place (a reused polytope keeps its capacity: the box-box sum's general path
  // allocates nothing).
  const Eigen::Matrix3d& R = box.rotation;
  out.vertices.resize(8), out.input_index.resize(8), out.faces.resize(6), out.edges.clear(), out.flat = false;
  for (int k = 0; k < 8; ++k) out.vertices[k] = box_corner(box, k), out.input_index[k] = k;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (int sign = 0; sign < 2; ++sign) {
      const int base = sign << a;
      // Corners around the face in the (b, c) plane: counter-clockwise about +axis a.
      Face& f = out.faces[2 * a + sign];
      f.loop.assign({base, base | (1 << b), base | (1 << b) | (1 << c), base | (1 << c)});
      f.normal = R.col(a);
      if (sign == 0) std::reverse(f.loop.begin(), f.loop.end()), f.normal = -f.normal;
      f.offset = f.normal.dot(out.vertices[f.loop[0]]);
    }
  }
  // The 12 edges (v0 < v1: the corners that differ in one bit), each with the faces whose loops
  // walk it either way.
  for (int v0 = 0; v0 < 8; ++v0)
    for (int a = 0; a < 3; ++a) {
      if (v0 >> a & 1) continue;
      Edge e{v0, v0 | 1 << a, -1, -1};
      for (int f = 0; f < 6; ++f)
        for (int k = 0; k < 4; ++k) {
          const int p = out.faces[f].loop[k], q = out.faces[f].loop[(k + 1) % 4];
          if (p == e.v0 && q == e.v1) e.left = f;
          if (p == e.v1 && q == e.v0) e.right = f;
        }
      out.edges.push_back(e);
    }
  return Status::Ok;
}

Status polytope_from_triangle(const Triangle& t, ConvexPolytope& out) {
  out = ConvexPolytope{};
  if (const Status s = check_triangle(t); s != Status::Ok) return s;
  return make_flat({t.a, t.b, t.c}, {0, 1, 2}, (t.b - t.a).cross(t.c - t.a).normalized(), out);
}

double support(const ConvexPolytope& p, const Vector3d& n, int* argmax) {
  double best = -std::numeric_limits<double>::infinity();
  int arg = -1;
  for (int k = 0; k < int(p.vertices.size()); ++k) {
    const double h = n.dot(p.vertices[k]);
    if (h > best) best = h, arg = k;
  }
  if (argmax) *argmax = arg;
  return best;
}

}  // namespace minksum
