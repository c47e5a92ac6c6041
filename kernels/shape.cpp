// Prepared convex shapes: a polytope validated once and its Gauss map laid out in flat arrays.
#include <algorithm>
#include <cmath>
#include <limits>

#include "shape_data.hpp"

namespace minksum {

using Eigen::Vector3d;

namespace detail {

namespace {

// The body-frame vertices, their size and the extent (bounding-box diagonal); false if a
// coordinate is not finite or beyond kMaxCoordinate.
bool take_vertices(const ConvexPolytope& p, ShapeData& s, double& extent) {
  const size_t V = p.vertices.size();
  s.px.resize(V), s.py.resize(V), s.pz.resize(V);
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  s.size = 0;
  for (size_t k = 0; k < V; ++k) {
    const Vector3d& v = p.vertices[k];
    if (!v.allFinite() || !(v.cwiseAbs().maxCoeff() <= kMaxCoordinate)) return false;
    s.px[k] = v.x(), s.py[k] = v.y(), s.pz[k] = v.z();
    lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    s.size = std::max(s.size, v.cwiseAbs().maxCoeff());
  }
  extent = V ? (hi - lo).norm() : 0;
  return true;
}

bool unit(const Vector3d& n) { return n.allFinite() && std::abs(n.squaredNorm() - 1) <= 1e-12; }

// A flat polygon: the thin prism of ShapeData's comment.
Status prepare_flat(const ConvexPolytope& p, ShapeData& s, double extent) {
  if (p.faces.size() != 2) return Status::InvalidMesh;
  const std::vector<int>& top = p.faces[0].loop;
  const int K = int(top.size()), V = int(p.vertices.size());
  const Vector3d n = p.faces[0].normal;
  if (K < 3 || K != V || !unit(n) || !((n + p.faces[1].normal).norm() <= 1e-12) ||
      !std::equal(top.begin(), top.end(), p.faces[1].loop.rbegin(), p.faces[1].loop.rend()))
    return Status::InvalidMesh;
  for (int v : top)
    if (v < 0 || v >= V || std::abs(n.dot(p.vertices[v] - p.vertices[top[0]])) > 1e-9 * extent) return Status::InvalidMesh;
  s.faces = K + 2, s.arcs = 3 * K, s.cells = 2 * K;
  s.nx.resize(size_t(s.faces)), s.ny.resize(size_t(s.faces)), s.nz.resize(size_t(s.faces));
  const auto set_normal = [&s](int f, const Vector3d& m) { s.nx[f] = m.x(), s.ny[f] = m.y(), s.nz[f] = m.z(); };
  set_normal(0, n), set_normal(1, -n);
  for (int k = 0; k < K; ++k) {
    const Vector3d d = p.vertices[top[(k + 1) % K]] - p.vertices[top[k]];
    const Vector3d side = d.cross(n);  // outward in the polygon's plane (its loop is counter-clockwise about n)
    if (!(side.norm() > 0)) return Status::InvalidMesh;
    set_normal(2 + k, side.normalized());
  }
  s.cell_vertex.resize(size_t(s.cells)), s.vertex_cell.resize(size_t(V));
  for (int c = 0; c < 2 * K; ++c) s.cell_vertex[c] = top[c % K];
  for (int k = 0; k < K; ++k) s.vertex_cell[top[k]] = k;
  // Cells: k is the top copy of top[k], K + k its bottom copy. Side k's loop is
  // top(k+1) -> top(k) -> bottom(k) -> bottom(k+1), which fixes the arcs' orientation.
  s.arc.resize(size_t(s.arcs)), s.dir.resize(size_t(s.arcs));
  const auto set_arc = [&](int e, ShapeData::Arc a, const Vector3d& d) { s.arc[e] = a, s.dir[e] = d; };
  for (int k = 0; k < K; ++k) {
    const int k1 = (k + 1) % K, side = 2 + k, prev_side = 2 + (k + K - 1) % K;
    const Vector3d d = p.vertices[top[k1]] - p.vertices[top[k]];
    set_arc(3 * k, {k, k1, 0, side}, d);                 // top face edge
    set_arc(3 * k + 1, {K + k1, K + k, 1, side}, -d);    // bottom face edge
    // The zero-length edge at top[k], from the top copy down: its arc's pole o_k x o_(k-1)
    // points along -n, so -n (times the polygon's width, the scale of the margins) stands
    // for its direction.
    set_arc(3 * k + 2, {k, K + k, side, prev_side}, -extent * n);
  }
  // Loops: top 0..K-1, bottom (K + K-1)..K, side k as above; arcs between consecutive cells.
  s.loop_start.assign(size_t(s.faces) + 1, 0);
  s.loop_cell.clear(), s.loop_arc.clear();
  const auto add = [&](int cell, int arc) { s.loop_cell.push_back(cell), s.loop_arc.push_back(arc); };
  for (int k = 0; k < K; ++k) add(k, 3 * k);
  s.loop_start[1] = K;
  for (int k = K - 1; k >= 0; --k) add(K + k, 3 * ((k + K - 1) % K) + 1);
  s.loop_start[2] = 2 * K;
  for (int k = 0; k < K; ++k) {
    const int k1 = (k + 1) % K;
    add(k1, 3 * k), add(k, 3 * k + 2), add(K + k, 3 * k + 1), add(K + k1, 3 * k1 + 2);
    s.loop_start[3 + k] = 2 * K + 4 * (k + 1);
  }
  return Status::Ok;
}

Status faces_from_polytope(const ConvexPolytope& p, double extent, ShapeData& s);

}  // namespace

Status prepare(const ConvexPolytope& p, ShapeData& s) {
  s.polytope_ref = &p;
  double extent = 0;
  if (!take_vertices(p, s, extent)) return Status::InvalidMesh;
  if (p.flat) {
    if (const Status st = prepare_flat(p, s, extent); st != Status::Ok) return st;
  } else {
    const int V = int(p.vertices.size()), F = int(p.faces.size()), E = int(p.edges.size());
    if (V < 4 || F < 4 || V - E + F != 2) return Status::InvalidMesh;
    s.faces = F, s.arcs = E, s.cells = V;
    s.nx.resize(size_t(F)), s.ny.resize(size_t(F)), s.nz.resize(size_t(F));
    for (int f = 0; f < F; ++f) {
      const Vector3d& n = p.faces[f].normal;
      if (!unit(n)) return Status::InvalidMesh;
      s.nx[f] = n.x(), s.ny[f] = n.y(), s.nz[f] = n.z();
    }
    s.arc.resize(size_t(E)), s.dir.resize(size_t(E));
    for (int e = 0; e < E; ++e) {
      const Edge& x = p.edges[e];
      if (x.v0 < 0 || x.v0 >= V || x.v1 < 0 || x.v1 >= V || x.v0 == x.v1 || x.left < 0 || x.left >= F ||
          x.right < 0 || x.right >= F || x.left == x.right)
        return Status::InvalidMesh;
      s.arc[e] = {x.v0, x.v1, x.left, x.right};
      s.dir[e] = p.vertices[x.v1] - p.vertices[x.v0];  // (convex at the edge: checked on the poles below)
    }
    s.cell_vertex.resize(size_t(V)), s.vertex_cell.resize(size_t(V));
    for (int v = 0; v < V; ++v) s.cell_vertex[v] = s.vertex_cell[v] = v;
  }
  // Every cell's arcs (a counting sort by cell); then each face's loop, with the arc of each
  // step found among its first cell's arcs, on the side the face must have it.
  s.cell_start.assign(size_t(s.cells) + 1, 0);
  for (const ShapeData::Arc& a : s.arc) ++s.cell_start[size_t(a.u) + 1], ++s.cell_start[size_t(a.v) + 1];
  for (int c = 0; c < s.cells; ++c) s.cell_start[c + 1] += s.cell_start[c];
  s.fill.assign(s.cell_start.begin(), s.cell_start.end() - 1);
  const size_t slots = size_t(2 * s.arcs);
  s.cell_slot.resize(slots), s.sx.resize(slots), s.sy.resize(slots), s.sz.resize(slots);
  s.arc_slot.resize(size_t(s.arcs)), s.arc_slot_v.resize(size_t(s.arcs));
  for (int e = 0; e < s.arcs; ++e) {
    const ShapeData::Arc& a = s.arc[e];
    s.arc_slot[e] = s.fill[a.u], s.arc_slot_v[e] = s.fill[a.v];
    s.cell_slot[s.fill[a.u]++] = {e, a.v};
    s.cell_slot[s.fill[a.v]++] = {~e, a.u};
  }
  fill_poles(s, false, s.nx.data(), s.ny.data(), s.nz.data(), s.sx.data(), s.sy.data(), s.sz.data());
  // Each pole along its edge (a prism's zero-length edges: along -normal): convex at every edge,
  // and the edges listed in the Edge orientation.
  s.pole_slack = 0;
  for (int e = 0; e < s.arcs; ++e) {
    const int k = s.arc_slot[e];
    const Vector3d c(s.sx[k], s.sy[k], s.sz[k]);
    if (!(s.dir[e].dot(c) > 0)) return Status::InvalidMesh;
    s.pole_slack = std::max(s.pole_slack, s.dir[e].normalized().cross(c.normalized()).norm());
  }
  for (int c = 0; c < s.cells; ++c)
    if (s.cell_start[c + 1] - s.cell_start[c] < 3) return Status::InvalidMesh;
  if (!p.flat && faces_from_polytope(p, extent, s) != Status::Ok) return Status::InvalidMesh;  // (a prism's are built)
  // Per loop step, the face across its arc; per face, where its loop has its smallest vertex
  // (the loops of the sum's facets start there).
  s.loop_face.resize(s.loop_arc.size()), s.loop_least.resize(size_t(s.faces));
  for (int f = 0; f < s.faces; ++f) {
    int least = s.loop_start[f];
    for (int k = s.loop_start[f]; k < s.loop_start[f + 1]; ++k) {
      const ShapeData::Arc& a = s.arc[s.loop_arc[k]];
      s.loop_face[k] = a.L == f ? a.R : a.L;
      if (s.cell_vertex[s.loop_cell[k]] < s.cell_vertex[s.loop_cell[least]]) least = k;
    }
    s.loop_least[f] = least - s.loop_start[f];
  }
  return Status::Ok;
}

void fill_poles(const ShapeData& s, bool swap, const double* nx, const double* ny, const double* nz, double* sx,
                double* sy, double* sz) {
  const ShapeData::Arc* arc = s.arc.data();
  const int *at_u = s.arc_slot.data(), *at_v = s.arc_slot_v.data();
  for (int e = 0; e < s.arcs; ++e) {
    const int l = swap ? arc[e].R : arc[e].L, r = swap ? arc[e].L : arc[e].R;
    const double x = ny[l] * nz[r] - nz[l] * ny[r], y = nz[l] * nx[r] - nx[l] * nz[r], z = nx[l] * ny[r] - ny[l] * nx[r];
    sx[at_u[e]] = x, sy[at_u[e]] = y, sz[at_u[e]] = z;
    sx[at_v[e]] = -x, sy[at_v[e]] = -y, sz[at_v[e]] = -z;
  }
}

namespace {

// The face loops of a solid, as cells and arcs, checked against the edges.
Status faces_from_polytope(const ConvexPolytope& p, double extent, ShapeData& s) {
  s.loop_start.assign(size_t(s.faces) + 1, 0);
  s.loop_cell.clear(), s.loop_arc.clear();
  s.side_used.assign(size_t(2 * s.arcs), 0);
  for (int f = 0; f < s.faces; ++f) {
    const Face& face = p.faces[f];
    const int n = int(face.loop.size());
    if (n < 3) return Status::InvalidMesh;
    const Vector3d& first = p.vertices[size_t(face.loop[0] >= 0 && face.loop[0] < s.cells ? face.loop[0] : 0)];
    for (int k = 0; k < n; ++k) {
      const int a = face.loop[k], b = face.loop[(k + 1) % n];
      if (a < 0 || a >= s.cells || b < 0 || b >= s.cells) return Status::InvalidMesh;
      if (std::abs(face.normal.dot(p.vertices[a] - first)) > 1e-9 * extent) return Status::InvalidMesh;
      int found = -1;
      for (int i = s.cell_start[a]; i < s.cell_start[a + 1]; ++i) {
        const ShapeData::Slot& slot = s.cell_slot[i];
        const int e = slot.arc >= 0 ? slot.arc : ~slot.arc;
        if (slot.next == b && (slot.arc >= 0 ? s.arc[e].L : s.arc[e].R) == f) found = e;
      }
      if (found < 0 || s.side_used[2 * found + (s.arc[found].u == a ? 0 : 1)]++) return Status::InvalidMesh;
      s.loop_cell.push_back(a), s.loop_arc.push_back(found);
    }
    s.loop_start[f + 1] = int(s.loop_cell.size());
  }
  if (int(s.loop_cell.size()) != 2 * s.arcs) return Status::InvalidMesh;  // every arc has two sides
  return Status::Ok;
}

}  // namespace

}  // namespace detail

namespace {
// An empty shape's polytope, built with the program (a function-local static would register
// its destructor on first use, an allocation inside the first real-time call).
const ConvexPolytope kEmptyPolytope;
}  // namespace

const ConvexPolytope& ConvexShape::polytope() const { return data_ ? *data_->polytope_ref : kEmptyPolytope; }

namespace {

// Takes a built polytope into a new shape.
Status adopt(Status built, ConvexPolytope&& p, ConvexShape& out) {
  out = ConvexShape{};
  if (built != Status::Ok) return built;
  auto data = std::make_shared<detail::ShapeData>();
  data->polytope = std::move(p);
  if (const Status s = detail::prepare(data->polytope, *data); s != Status::Ok) return s;
  data->fill = {}, data->side_used = {}, data->dir = {};  // scratch of prepare
  detail::ShapeAccess::set(std::move(data), out);
  return Status::Ok;
}

}  // namespace

Status shape_from_points(const std::vector<Vector3d>& points, ConvexShape& out) {
  ConvexPolytope p;
  const Status s = polytope_from_points(points, p);
  return adopt(s, std::move(p), out);
}

Status shape_from_mesh(const std::vector<Vector3d>& vertices, const std::vector<std::vector<int>>& faces,
                       ConvexShape& out) {
  ConvexPolytope p;
  const Status s = polytope_from_mesh(vertices, faces, p);
  return adopt(s, std::move(p), out);
}

Status shape_from_box(const Box& box, ConvexShape& out) {
  ConvexPolytope p;
  const Status s = polytope_from_box(box, p);
  return adopt(s, std::move(p), out);
}

Status shape_from_triangle(const Triangle& t, ConvexShape& out) {
  ConvexPolytope p;
  const Status s = polytope_from_triangle(t, p);
  return adopt(s, std::move(p), out);
}

Status shape_from_polytope(const ConvexPolytope& p, ConvexShape& out) {
  return adopt(Status::Ok, ConvexPolytope(p), out);
}

[[gnu::flatten]] Status check_pose(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d R = pose.linear();
  const Vector3d t = pose.translation();
  if (!R.allFinite() || !t.allFinite()) return Status::InvalidPose;
  if (!(t.cwiseAbs().maxCoeff() <= kMaxCoordinate)) return Status::InvalidPose;
  // A proper rotation: orthonormal columns (to 1e-9) and a right-handed frame.
  if (!((R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() <= 1e-9) || !(R.determinant() > 0))
    return Status::InvalidPose;
  return Status::Ok;
}

}  // namespace minksum
