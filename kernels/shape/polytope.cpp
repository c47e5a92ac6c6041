// Building and validating convex polytopes (boxes, triangles, point sets, explicit meshes).
#include <minksum/model.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/hull.hpp"
#include "core/predicates.hpp"

namespace minksum {

using Eigen::Vector3d;

const char* to_string(Status s) {
  switch (s) {
    case Status::Ok: return "ok";
    case Status::NonFinite: return "a coordinate is NaN or Inf";
    case Status::OutOfRange: return "a coordinate's magnitude exceeds 1e100";
    case Status::TooFewPoints: return "fewer than 3 distinct points";
    case Status::Collinear: return "all points are collinear (a segment is not a polytope)";
    case Status::InvalidMesh: return "invalid mesh (bad index, short or degenerate face, open or non-manifold)";
    case Status::NotConvex: return "the mesh is not convex";
    case Status::InvalidBox: return "invalid box (non-positive half extent or non-orthonormal rotation)";
    case Status::DegenerateResult: return "the sum of two coplanar flat polytopes is flat, not a solid";
    case Status::HullFailed: return "the convex hull (Qhull) failed";
    case Status::InvalidPose: return "the pose is not a finite rigid motion (a proper rotation and a translation)";
  }
  return "unknown status";
}

namespace {

// Relative thresholds, in units of the input's bounding-box diagonal D. Points closer than
// kFlatTol * D to a plane make the input flat; closer than kLineTol * D to a line, collinear.
constexpr double kFlatTol = 1e-10;
constexpr double kLineTol = 1e-12;

// NonFinite for NaN/Inf, OutOfRange beyond kMaxCoordinate, else Ok.
Status check_coordinates(const Vector3d* pts, size_t n) {
  for (size_t k = 0; k < n; ++k)
    if (!pts[k].allFinite()) return Status::NonFinite;
  for (size_t k = 0; k < n; ++k)
    if (!(pts[k].cwiseAbs().maxCoeff() <= kMaxCoordinate)) return Status::OutOfRange;
  return Status::Ok;
}
Status check_coordinates(const std::vector<Vector3d>& pts) { return check_coordinates(pts.data(), pts.size()); }

double diagonal(const Vector3d* pts, size_t n) {
  Vector3d lo = pts[0], hi = pts[0];
  for (size_t k = 0; k < n; ++k) lo = lo.cwiseMin(pts[k]), hi = hi.cwiseMax(pts[k]);
  return (hi - lo).norm();
}
double diagonal(const std::vector<Vector3d>& pts) { return diagonal(pts.data(), pts.size()); }

// Fills `edges` from the face loops; false unless every directed edge has exactly one twin.
bool edges_from_loops(ConvexPolytope& p) {
  std::map<std::pair<int, int>, int> directed;
  for (int f = 0; f < int(p.faces.size()); ++f) {
    const auto& loop = p.faces[f].loop;
    for (size_t k = 0; k < loop.size(); ++k) {
      const auto key = std::make_pair(loop[k], loop[(k + 1) % loop.size()]);
      if (!directed.emplace(key, f).second) return false;
    }
  }
  p.edges.clear();
  for (const auto& [key, f] : directed) {
    if (key.first > key.second) continue;
    auto twin = directed.find({key.second, key.first});
    if (twin == directed.end()) return false;
    p.edges.push_back(Edge{key.first, key.second, f, twin->second});
  }
  return p.edges.size() * 2 == directed.size();
}

// Flat polytope from a counter-clockwise (about n) loop of the points `pts`.
Status make_flat(const std::vector<Vector3d>& pts, const std::vector<int>& loop_ids,
                 const Vector3d& n, ConvexPolytope& out) {
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
  // Exact duplicates are dropped, keeping the first index (Qhull would keep an arbitrary one).
  std::vector<int> order(points.size());
  for (int k = 0; k < int(points.size()); ++k) order[k] = k;
  auto lex = [&](int a, int b) {
    return std::lexicographical_compare(points[a].data(), points[a].data() + 3, points[b].data(),
                                        points[b].data() + 3);
  };
  std::stable_sort(order.begin(), order.end(), lex);
  std::vector<int> unique_ids;
  for (size_t k = 0; k < order.size(); ++k)
    if (k == 0 || points[order[k]] != points[order[k - 1]]) unique_ids.push_back(order[k]);
  std::sort(unique_ids.begin(), unique_ids.end());
  if (unique_ids.size() < 3) return Status::TooFewPoints;

  std::vector<Vector3d> pts;
  for (int id : unique_ids) pts.push_back(points[id]);
  const double D = diagonal(pts);
  // Two far-apart points, then the point farthest from their line, then from their plane.
  auto farthest = [&](auto dist) {
    int best = 0;
    for (int k = 1; k < int(pts.size()); ++k)
      if (dist(pts[k]) > dist(pts[best])) best = k;
    return best;
  };
  const int p1 = farthest([&](const Vector3d& p) { return (p - pts[0]).squaredNorm(); });
  const Vector3d axis = (pts[p1] - pts[0]).normalized();
  auto line_dist = [&](const Vector3d& p) { return (p - pts[0]).cross(axis).norm(); };
  const int p2 = farthest(line_dist);
  if (line_dist(pts[p2]) <= kLineTol * D) return Status::Collinear;
  const Vector3d n = axis.cross(pts[p2] - pts[0]).normalized();
  auto plane_dist = [&](const Vector3d& p) { return std::abs(n.dot(p - pts[0])); };
  if (plane_dist(pts[farthest(plane_dist)]) <= kFlatTol * D) {
    std::vector<int> all(pts.size());
    for (int k = 0; k < int(pts.size()); ++k) all[k] = k;
    std::vector<int> loop = detail::planar_hull(pts, all, n, kLineTol * D * D);
    if (loop.size() < 3) return Status::Collinear;
    for (int& id : loop) id = unique_ids[id];
    return make_flat(points, loop, n, out);
  }

  std::vector<detail::HullFacet> facets;
  if (!detail::qhull_facets(pts, facets)) return Status::HullFailed;
  std::map<int, int> remap;  // index into pts -> vertex index, in input order
  for (const auto& f : facets)
    for (int id : f.loop) remap.emplace(id, 0);
  for (auto& [id, v] : remap) {
    v = int(out.vertices.size());
    out.vertices.push_back(pts[id]);
    out.input_index.push_back(unique_ids[id]);
  }
  for (const auto& f : facets) {
    Face face{{}, f.normal, 0.0};
    for (int id : f.loop) face.loop.push_back(remap[id]);
    // Qhull's normal depends on which points built the facet; the exact Newell normal depends
    // on the face alone, so faces that are exactly parallel stay exactly parallel.
    const Vector3d newell = detail::exact_newell(out.vertices, face.loop);
    if (newell.norm() > 0) face.normal = newell.normalized();
    face.offset = -std::numeric_limits<double>::infinity();
    for (int v : face.loop) face.offset = std::max(face.offset, f.normal.dot(out.vertices[v]));
    out.faces.push_back(std::move(face));
  }
  return edges_from_loops(out) ? Status::Ok : Status::HullFailed;
}

Status polytope_from_mesh(const std::vector<Vector3d>& vertices,
                          const std::vector<std::vector<int>>& faces, ConvexPolytope& out) {
  out = ConvexPolytope{};
  if (const Status s = check_coordinates(vertices); s != Status::Ok) return s;
  if (vertices.size() < 4 || faces.size() < 4) return Status::InvalidMesh;
  const double D = diagonal(vertices);
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
    for (size_t k = 0; k < loop.size(); ++k)
      n += vertices[loop[k]].cross(vertices[loop[(k + 1) % loop.size()]]);
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
  const double det = (r[1] * r[5] - r[2] * r[4]) * r[6] + (r[2] * r[3] - r[0] * r[5]) * r[7] +
                     (r[0] * r[4] - r[1] * r[3]) * r[8];
  if (!(worst <= 1e-9) || det < 0) return Status::InvalidBox;
  return Status::Ok;
}

Vector3d box_corner(const Box& box, int code) {
  Vector3d p = box.center;
  for (int a = 0; a < 3; ++a)
    p += ((code >> a & 1) ? 1.0 : -1.0) * box.half_extents[a] * box.rotation.col(a);
  return p;
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

Status check_triangle(const Triangle& t) {
  const Vector3d pts[3] = {t.a, t.b, t.c};
  if (const Status s = check_coordinates(pts, 3); s != Status::Ok) return s;
  if (t.a == t.b || t.b == t.c || t.a == t.c) return Status::TooFewPoints;
  const double D = diagonal(pts, 3);
  // Relative to the diagonal first: the cross product of raw edges overflows beyond 1e154.
  if (((t.b - t.a) / D).cross((t.c - t.a) / D).norm() <= kLineTol) return Status::Collinear;
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
