// How a convex tool touches a mesh (haptic rendering): the mesh's triangles clipped by the tool
// (clip_triangle), their parts inside gathered through the octree (gather_parts), and the depth
// the tool must move to push them out (push_out). A rounded tool instead takes the triangles
// within its radius of the core and the exact exit of each (contact_rounded).
#include <minksum/kernels.hpp>
#include "mesh/placed_core.hpp"
#include "geometry/closest.hpp"
#include "shape/shape_data.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using detail::MeshScratch;
using detail::PlacedCore;
using detail::unit_normal;
using Eigen::Vector3d;

namespace {

constexpr int kMaxPlanes = 2 * kMaxToolVertices;

// The tool in A's frame: its face planes (n . x <= o inside; the normals also as SoA for the
// corner tests) and its bounding box.
struct ToolPlanes {
  int count = 0;
  const detail::MapLayout* map = nullptr;  // the faces' adjacency (across each edge), if known
  Vector3d n[kMaxPlanes];
  double o[kMaxPlanes];
  alignas(64) double nx[kMaxPlanes], ny[kMaxPlanes], nz[kMaxPlanes];
  Vector3d lo, hi;
};

// Room for one clip: two polygons (a triangle cut by every plane gains a corner per plane) and
// the per-plane corner tests.
struct ClipScratch {
  Vector3d poly[2][3 + kMaxPlanes];
  alignas(64) double above[kMaxPlanes], below[kMaxPlanes];
  int cut[kMaxPlanes];
};

// Whether a face's plane separates triangle t from the tool: a climb over the faces (across
// their edges, to the neighbour whose plane leaves the corners farthest beyond) from `hint`,
// the face the last climb ended on. Neighbouring triangles are separated by the same face or
// one a few edges away, so most triangles near a tool of hundreds of faces are rejected after
// a few dozen planes, not all. Where the climb stalls without a gap, the full pass decides.
bool climb_separates(const ToolPlanes& tool, const Vector3d (&t)[3], int& hint) {
  const auto gap = [&](int f) {
    return std::min({tool.n[f].dot(t[0]), tool.n[f].dot(t[1]), tool.n[f].dot(t[2])}) - tool.o[f];
  };
  const detail::MapLayout& map = *tool.map;
  int f = hint;
  double g = gap(f);
  for (int step = 0; step < tool.count && !(g > 0); ++step) {  // (each step gains: no cycle)
    int best = -1;
    for (int k = map.loop_start[f]; k < map.loop_start[f + 1]; ++k)
      if (const double x = gap(map.loop_face[k]); x > g) best = map.loop_face[k], g = x;
    if (best < 0) break;
    f = best;
  }
  hint = f;
  return g > 0;
}

// The part of triangle t inside the tool: its corner count (0: they do not meet), the corners
// at `poly`. First every plane against the three corners at once (a loop the compiler
// vectorises): a plane with all corners beyond it rejects the triangle, and only the planes
// with a corner beyond can cut it; a plane with every corner inside leaves every point of the
// triangle inside, so clipping by it would change nothing (to rounding). Then
// Sutherland-Hodgman (1974) over the cutting planes: O(faces) per triangle.
int clip_triangle(const ToolPlanes& tool, const Vector3d (&t)[3], ClipScratch& s, const Vector3d*& poly, int& hint) {
  if (tool.map && climb_separates(tool, t, hint)) return 0;
  const int nf = tool.count;
  for (int f = 0; f < nf; ++f) {
    const double d0 = tool.nx[f] * t[0].x() + tool.ny[f] * t[0].y() + tool.nz[f] * t[0].z() - tool.o[f];
    const double d1 = tool.nx[f] * t[1].x() + tool.ny[f] * t[1].y() + tool.nz[f] * t[1].z() - tool.o[f];
    const double d2 = tool.nx[f] * t[2].x() + tool.ny[f] * t[2].y() + tool.nz[f] * t[2].z() - tool.o[f];
    s.above[f] = std::max(std::max(d0, d1), d2), s.below[f] = std::min(std::min(d0, d1), d2);
  }
  double reject = -1;
  for (int f = 0; f < nf; ++f) reject = std::max(reject, s.below[f]);
  if (reject > 0) return 0;
  int ncut = 0;
  for (int f = 0; f < nf; ++f) s.cut[ncut] = f, ncut += s.above[f] > 0;
  int m = 3, cur = 0;
  for (int k = 0; k < 3; ++k) s.poly[0][k] = t[k];
  for (int i = 0; i < ncut && m > 0; ++i) {
    const Vector3d& n = tool.n[s.cut[i]];
    const double o = tool.o[s.cut[i]];
    int out_m = 0;
    for (int k = 0; k < m; ++k) {
      const Vector3d &p = s.poly[cur][k], &q = s.poly[cur][(k + 1) % m];
      const double dp = n.dot(p) - o, dq = n.dot(q) - o;
      if (dp <= 0) s.poly[1 - cur][out_m++] = p;
      if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) s.poly[1 - cur][out_m++] = p + dp / (dp - dq) * (q - p);
    }
    m = out_m, cur = 1 - cur;
  }
  poly = s.poly[cur];
  return m;
}

void triangle_corners(const Octree& a, int tri, Vector3d (&t)[3]) {
  for (int k = 0; k < 3; ++k) t[k] = a.vertices[a.triangles[tri][k]];
}

// The overlapped triangles (each once: a triangle is listed in one leaf), their parts inside
// the tool in ws.parts, and the area vector of those parts, whose direction is the push-out
// direction (a sum over the contact patch: it turns continuously as the tool slides, unlike any
// single triangle's normal), and their area and its first moment (out.area, out.centre times
// the area). Returns how many triangles were hit; their indices go to `hit`.
int gather_parts(const Octree& a, const ToolPlanes& tool, MeshScratch& ws, int (&hit)[kMaxContactTriangles],
                 Vector3d& area, MeshContact& out) {
  const Vector3d box_c = (tool.lo + tool.hi) / 2, box_h = (tool.hi - tool.lo) / 2;
  ClipScratch scratch;
  int hits = 0, hint = 0;
  ws.part_start[0] = 0;
  area = Vector3d::Zero();
  int stack[8 * 25 + 8], top = 0;  // depth <= 24 (OctreeOptions): at most 7 more per level
  stack[top++] = 0;
  while (top > 0) {
    const Octree::Node& n = a.nodes[stack[--top]];
    if (((n.box_center - box_c).cwiseAbs() - n.box_half - box_h).maxCoeff() > 0) continue;
    if (n.first_child >= 0) {
      for (int c = n.first_child; c < n.first_child + n.child_count; ++c) stack[top++] = c;
      continue;
    }
    for (int x = n.first; x < n.first + n.count; ++x) {
      const int tri = a.items[x];
      Vector3d t[3];
      triangle_corners(a, tri, t);
      const Vector3d tlo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), thi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
      if ((tlo.array() > tool.hi.array()).any() || (thi.array() < tool.lo.array()).any()) continue;
      ++out.tested;
      const Vector3d* poly;
      const int m = clip_triangle(tool, t, scratch, poly, hint);
      if (m == 0) continue;
      if (hits == kMaxContactTriangles || ws.part_start[hits] + m > int(ws.parts.size())) {
        out.overflow = true;  // more contact than capacity: flagged, the first parts count
        continue;
      }
      hit[hits] = tri;
      std::copy(poly, poly + m, ws.parts.begin() + ws.part_start[hits]);
      ws.part_start[hits + 1] = ws.part_start[hits] + m;
      ++hits;
      for (int k = 1; k + 1 < m; ++k) {  // the part as a fan of triangles
        const Vector3d a2 = (poly[k] - poly[0]).cross(poly[k + 1] - poly[0]);
        const double size = detail::norm_of(a2) / 2;
        area += a2 / 2, out.area += size, out.centre += size * (poly[0] + poly[k] + poly[k + 1]) / 3;
      }
    }
  }
  return hits;
}

// How far the tool must move along u until no part is inside it: for each corner p of the
// parts, the ray p - lambda u stays in the tool until the first face it leaves by.
void push_out(const ToolPlanes& tool, const MeshScratch& ws, const int* hit, int hits, const Vector3d& u,
              MeshContact& out) {
  // The faces a ray along -u can leave by, as arrays (normal, offset, and how fast the ray
  // approaches the plane), so that the corners' loop over them vectorises.
  alignas(64) double fx[kMaxPlanes], fy[kMaxPlanes], fz[kMaxPlanes], fo[kMaxPlanes], rate[kMaxPlanes];
  int nfacing = 0;
  for (int f = 0; f < tool.count; ++f) {
    const double along = tool.n[f].dot(u);
    if (!(along < 0)) continue;
    fx[nfacing] = tool.nx[f], fy[nfacing] = tool.ny[f], fz[nfacing] = tool.nz[f], fo[nfacing] = tool.o[f];
    rate[nfacing++] = -along;
  }
  int exit = 0, leaving = 0;  // the face the last corner leaves by
  for (int h = 0; h < hits; ++h) {
    for (int k = ws.part_start[h]; k < ws.part_start[h + 1]; ++k) {
      const Vector3d& p = ws.parts[k];
      const double px = p.x(), py = p.y(), pz = p.z();
      // Only a corner deeper than the deepest so far counts: its scan stops at the first face
      // that lets it out sooner, tried first where the last corner left (neighbours leave by
      // the same face), so most corners cost a face or two, not all.
      const bool first = out.triangle < 0;
      double lambda = std::numeric_limits<double>::infinity();
      for (int j = 0; j < nfacing && (first || lambda > out.penetration_depth); ++j) {
        const int i = j == 0 ? exit : j == exit ? 0 : j;
        const double t = std::max(0.0, fo[i] - (fx[i] * px + fy[i] * py + fz[i] * pz)) / rate[i];
        if (t < lambda) lambda = t, leaving = i;
      }
      exit = leaving;
      if (std::isfinite(lambda) && (lambda > out.penetration_depth || first))
        out.penetration_depth = lambda, out.point = p, out.triangle = hit[h];
    }
  }
}

// The core's vertices, edges and faces ranked along the push-out direction u: how high each
// reaches along u in (t (-) core), less t's part (-u . v, the largest over the feature).
struct CoreTops {
  double vertex[kMaxToolVertices], edge[3 * kMaxToolVertices], face[detail::kMaxCoreTriangles];
  int edges = 0;
  double top = -std::numeric_limits<double>::infinity();

  CoreTops(const PlacedCore& core, const Vector3d& u) {
    for (int j = 0; j < core.vertices; ++j) vertex[j] = -u.dot(core.v[j]), top = std::max(top, vertex[j]);
    edges = core.line ? core.vertices - 1 : int(core.shape->edges.size());
    for (int e = 0; e < edges; ++e) {
      const auto [a, b] = ends(core, e);
      edge[e] = std::max(vertex[a], vertex[b]);
    }
    for (int f = 0; f < core.faces; ++f) {
      face[f] = -std::numeric_limits<double>::infinity();
      for (const int j : core.shape->faces[size_t(f)].loop) face[f] = std::max(face[f], vertex[j]);
    }
  }
  // Edge e's vertices (a segment's one edge joins its ends).
  static std::pair<int, int> ends(const PlacedCore& core, int e) {
    if (core.line) return {0, core.vertices - 1};
    const Edge& x = core.shape->edges[size_t(e)];
    return {x.v0, x.v1};
  }
};

// Where the ray lambda u leaves (t (-) core) (+) B(r), if beyond `best` (else best): the largest
// exit of the pieces it is the union of (detail::ball_exit). The faces of a Minkowski sum are
// sums of the operands' features (the paper's section 3: a vertex and a face, two edges), so the
// pieces are the balls about t_i - v_j, the cylinders about t_i - (a core edge) and (an edge of
// t) - v_j, and the slabs over t_i - (a core face), t - v_j and (an edge of t) - (a core edge).
// A piece reaches at most its highest point along u plus r: one that cannot pass `best` is
// skipped, so only the few pieces near the top along u are solved.
double difference_exit(const PlacedCore& core, const CoreTops& tops, const Vector3d (&t)[3], const Vector3d& u,
                       double r, double best) {
  const double ut[3] = {u.dot(t[0]), u.dot(t[1]), u.dot(t[2])};
  const double high = std::max({ut[0], ut[1], ut[2]});
  if (!(high + tops.top + r > best)) return best;
  const Vector3d* v = core.v;
  Vector3d nt = unit_normal(t);
  int order[3] = {0, 1, 2};
  if (nt.dot(u) < 0) nt = -nt, std::swap(order[1], order[2]);  // (the side of t facing u)
  for (int j = 0; j < core.vertices; ++j) {
    if (!(high + tops.vertex[j] + r > best)) continue;
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3;
      if (ut[i] + tops.vertex[j] + r > best) best = std::max(best, detail::ball_exit(t[i] - v[j], u, r));
      if (std::max(ut[i], ut[i1]) + tops.vertex[j] + r > best)
        best = std::max(best, detail::cylinder_exit(t[i] - v[j], t[i1] - v[j], u, r));
    }
    const auto corner = [&](int e) { return Vector3d(t[order[e]] - v[j]); };
    best = std::max(best, detail::slab_exit(corner, 3, nt, nt.dot(t[0] - v[j]), u, r));
  }
  for (int e = 0; e < tops.edges; ++e) {
    if (!(high + tops.edge[e] + r > best)) continue;
    const auto [a, b] = CoreTops::ends(core, e);
    for (int i = 0; i < 3; ++i) {
      const int i1 = (i + 1) % 3;
      if (ut[i] + tops.edge[e] + r > best) best = std::max(best, detail::cylinder_exit(t[i] - v[a], t[i] - v[b], u, r));
      if (!(std::max(ut[i], ut[i1]) + tops.edge[e] + r > best)) continue;
      Vector3d m = (t[i1] - t[i]).cross(v[a] - v[b]);
      const double len = detail::norm_of(m);
      if (!(len > 0)) continue;  // (parallel edges: the cylinders cover their strip)
      m /= len;
      // (t_i - v_a, t_i1 - v_a, t_i1 - v_b, t_i - v_b) turns counter-clockwise about m.
      const Vector3d c[4] = {t[i] - v[a], t[i1] - v[a], t[i1] - v[b], t[i] - v[b]};
      const bool flip = m.dot(u) < 0;
      const auto corner = [&](int k) { return c[flip ? 3 - k : k]; };
      best = std::max(best, detail::slab_exit(corner, 4, flip ? Vector3d(-m) : m, (flip ? -m : m).dot(c[0]), u, r));
    }
  }
  for (int f = 0; f < core.faces; ++f) {
    const Vector3d nf = -core.n[f];  // (the face of -core: its normal turned, its loop reversed)
    if (!(high + tops.face[f] + r > best) || !(nf.dot(u) > 0)) continue;
    const std::vector<int>& loop = core.shape->faces[size_t(f)].loop;
    const int k = int(loop.size());
    for (int i = 0; i < 3; ++i) {
      if (!(ut[i] + tops.face[f] + r > best)) continue;
      const auto corner = [&](int e) { return Vector3d(t[i] - v[loop[size_t(k - 1 - e)]]); };
      best = std::max(best, detail::slab_exit(corner, k, nf, nf.dot(t[i]) + core.o[f], u, r));
    }
  }
  return best;
}

// A rounded tool (a sphere, a capsule, a radius on any shape): every triangle within the radius
// r of the core touches it, found through the octree (node boxes against the core's box grown
// by r, then the exact distance d). The direction is the triangles' outward normals weighted by
// their depths r - d, each term vanishing as its triangle leaves: it turns continuously as the
// tool slides, and on a flat patch it is the patch's normal. The depth is exact: how far the
// tool moves along u until every triangle lies r from the core, the largest exit of the ray
// from (t (-) core) (+) B(r) (difference_exit), for the triangles in contact. Parts are not
// clipped: the area is 0.
Status contact_rounded(const Octree& a, const ConvexShape& shape, const detail::Rigid& pose, MeshContact& out) {
  PlacedCore core;
  if (const Status s = detail::place_core(shape, pose, core); s != Status::Ok) return s;
  const double r = shape.radius();
  const Vector3d box_c = core.box_c, box_h = core.box_h.array() + r, lo = box_c - box_h, hi = box_c + box_h;
  int hit[kMaxContactTriangles], hits = 0;
  Vector3d near[kMaxContactTriangles];
  Vector3d u = Vector3d::Zero();
  double total = 0, least = std::numeric_limits<double>::infinity();
  int stack[8 * 25 + 8], top = 0;  // depth <= 24 (OctreeOptions): at most 7 more per level
  stack[top++] = 0;
  while (top > 0) {
    const Octree::Node& n = a.nodes[size_t(stack[--top])];
    if (((n.box_center - box_c).cwiseAbs() - n.box_half - box_h).maxCoeff() > 0) continue;
    if (n.first_child >= 0) {
      for (int c = n.first_child; c < n.first_child + n.child_count; ++c) stack[top++] = c;
      continue;
    }
    for (int x = n.first; x < n.first + n.count; ++x) {
      const Vector3d* t = &a.item_corners[3 * size_t(x)];
      const Vector3d tlo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), thi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
      if ((tlo.array() > hi.array()).any() || (thi.array() < lo.array()).any()) continue;
      ++out.tested;
      const Vector3d tri[3] = {t[0], t[1], t[2]};
      Vector3d on_t, on_core;
      const double d = core.distance(tri, on_t, on_core, r);
      if (!(d <= r)) continue;
      if (hits == kMaxContactTriangles) {
        out.overflow = true;  // more contact than capacity: flagged, the first ones count
        continue;
      }
      hit[hits] = a.items[size_t(x)], near[hits] = on_t;
      u += (r - d) * detail::unit_normal(tri), total += r - d;
      out.centre += (r - d) * on_core, least = std::min(least, d);
      ++hits;
    }
  }
  if (hits == 0) return Status::Ok;
  out.intersecting = true;
  if (u.norm() > 0) {
    u.normalize();
  } else {  // (touching only, or normals that cancel: a sheet pinched from both sides)
    Vector3d tri[3];
    triangle_corners(a, hit[0], tri);
    u = detail::unit_normal(tri);
  }
  out.penetration_direction = u;
  // The core's nearest points weighted as the direction, moved down to the nearest triangle's
  // level along it: a sphere's foot on a flat patch, a capsule's contact line's middle there.
  out.centre = total > 0 ? Vector3d(out.centre / total - least * u) : near[0];
  if (u.isZero()) return Status::Ok;  // (a degenerate triangle alone: no direction to push along)
  const CoreTops tops(core, u);
  double best = -std::numeric_limits<double>::infinity();
  for (int h = 0; h < hits; ++h) {
    Vector3d tri[3];
    triangle_corners(a, hit[h], tri);
    const double lambda = difference_exit(core, tops, tri, u, r, best);
    if (lambda > best || out.triangle < 0) best = lambda, out.point = near[h], out.triangle = hit[h];
  }
  out.penetration_depth = std::max(best, 0.0);
  return Status::Ok;
}

// mesh_contact with the tool placed in A's frame by `pose`.
Status contact_in_a(const Octree& a, const ConvexShape& shape, const detail::Rigid& pose, MeshScratch& ws,
                    MeshContact& out) {
  if (a.nodes.empty() || shape.empty()) return Status::TooFewPoints;
  if (shape.radius() > 0) return contact_rounded(a, shape, pose, out);  // (a sphere or a capsule has one)
  const ConvexPolytope& polytope = shape.polytope();
  const int nv = int(polytope.vertices.size());
  if (nv > kMaxToolVertices || polytope.faces.size() > size_t(kMaxPlanes)) return Status::CapacityExceeded;
  if (polytope.flat || nv < 4) return Status::InvalidMesh;  // (no inside to clip by)
  ToolPlanes tool;
  tool.lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), tool.hi = -tool.lo;
  for (int k = 0; k < nv; ++k) {
    const Vector3d v = pose.point(polytope.vertices[k]);
    tool.lo = tool.lo.cwiseMin(v), tool.hi = tool.hi.cwiseMax(v);
  }
  tool.count = int(polytope.faces.size());
  // The climb pays where the faces are many (a box's six are cheaper all at once).
  const detail::ShapeData* data = detail::ShapeAccess::data(shape);
  if (tool.count > 32 && data && data->faces == tool.count) tool.map = &data->map[0];
  for (int f = 0; f < tool.count; ++f) {
    pose.plane(polytope.faces[f].normal, polytope.faces[f].offset, tool.n[f], tool.o[f]);
    tool.nx[f] = tool.n[f].x(), tool.ny[f] = tool.n[f].y(), tool.nz[f] = tool.n[f].z();
  }
  int hit[kMaxContactTriangles];
  Vector3d area;
  const int hits = gather_parts(a, tool, ws, hit, area, out);
  if (hits == 0) return Status::Ok;
  out.intersecting = true;
  if (out.area > 0) out.centre /= out.area;
  else out.centre = ws.parts[0];  // parts of no area (a corner or an edge grazing the tool)
  const double len = detail::norm_of(area);
  Vector3d u = len > 0 ? Vector3d(area / len) : Vector3d::Zero();
  if (u.isZero()) {  // parts facing both ways cancel (a sheet pinched from both sides)
    Vector3d t[3];
    triangle_corners(a, hit[0], t);
    u = detail::unit_normal(t);
  }
  out.penetration_direction = u;
  push_out(tool, ws, hit, hits, u, out);
  return Status::Ok;
}

}  // namespace

Status mesh_contact(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                    const Eigen::Isometry3d& pose_tool, MeshWorkspace& ws, MeshContact& out) {
  out = MeshContact{};
  if (!ws.scratch()) return Status::WorkspaceMismatch;  // not a workspace from make_workspace
  detail::Rigid pose;
  if (const Status s = detail::relative_pose(pose_a, pose_tool, pose); s != Status::Ok) return s;
  const Status s = contact_in_a(a, shape, pose, *ws.scratch(), out);
  if (out.intersecting) out.penetration_direction = pose_a.linear() * out.penetration_direction;
  if (out.triangle >= 0) out.point = pose_a * out.point;
  if (out.intersecting) out.centre = pose_a * out.centre;
  return s;
}

}  // namespace minksum
