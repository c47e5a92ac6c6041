// Prepared convex shapes: a polytope validated once and its Gauss map laid out in flat arrays.
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "core/predicates.hpp"
#include "core/validate.hpp"
#include "shape/shape_data.hpp"

namespace minksum {

using Eigen::Vector3d;

namespace detail {

namespace {

// The body-frame vertices, their size and the extent (bounding-box diagonal); false if a
// coordinate is not finite or beyond kMaxCoordinate.
bool take_vertices(const ConvexPolytope& p, ShapeData& s, double& extent) {
  const size_t V = p.vertices.size();
  if (detail::check_coordinates(p.vertices.data(), V) != Status::Ok) return false;
  s.px.resize(V), s.py.resize(V), s.pz.resize(V);
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  s.size = 0;
  for (size_t k = 0; k < V; ++k) {
    const Vector3d& v = p.vertices[k];
    s.px[k] = v.x(), s.py[k] = v.y(), s.pz[k] = v.z();
    lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
    s.size = std::max(s.size, v.cwiseAbs().maxCoeff());
  }
  extent = V ? (hi - lo).norm() : 0;
  return true;
}

// Whether a nonzero coordinate is under kTinyComponent (2^-300) of the largest magnitude.
bool tiny_coordinates(const ShapeData& s) {
  const double floor = detail::kTinyComponent * s.size;
  for (const std::vector<double>* c : {&s.px, &s.py, &s.pz})
    for (double x : *c)
      if (x != 0 && std::abs(x) < floor) return true;
  return false;
}

bool unit(const Vector3d& n) { return n.allFinite() && std::abs(n.squaredNorm() - 1) <= 1e-12; }

// What prepare builds a layout from: the arcs (u, v; faces found from the loops) and each
// face's loop of cells, counter-clockwise from outside.
struct Topology {
  std::vector<int> arc_u, arc_v;
  std::vector<int> loop_start, loop_cell;
};

// A flat polygon: the thin prism of ShapeData's comment.
Status prepare_flat(const ConvexPolytope& p, ShapeData& s, double extent, Topology& t) {
  if (p.faces.size() != 2) return Status::InvalidMesh;
  const std::vector<int>& top = p.faces[0].loop;
  const int K = int(top.size()), V = int(p.vertices.size());
  const Vector3d n = p.faces[0].normal;
  if (K < 3 || K != V || !unit(n) || !((n + p.faces[1].normal).norm() <= 1e-12) ||
      !std::equal(top.begin(), top.end(), p.faces[1].loop.rbegin(), p.faces[1].loop.rend()))
    return Status::InvalidMesh;
  for (int v : top)
    if (v < 0 || v >= V || std::abs(n.dot(p.vertices[v] - p.vertices[top[0]])) > 1e-9 * extent)
      return Status::InvalidMesh;
  s.faces = K + 2, s.arcs = 3 * K, s.cells = 2 * K;
  s.gauss.resize(size_t(s.faces));
  s.gauss_terms.clear(), s.gauss_term_start.assign(1, 0), s.gauss_kind.resize(size_t(s.faces));
  std::vector<double>& terms = s.gauss_terms;
  const auto set_normal = [&s](int f, const Vector3d& m, const int count[3]) {
    s.gauss[f] = m;
    s.gauss_kind[f] = count[0] + count[1] + count[2] ? GaussKind::Stored : GaussKind::Exact;
    for (int k = 0; k < 3; ++k) s.gauss_term_start.push_back(s.gauss_term_start.back() + count[k]);
  };
  // The top face's exact normal (stored: the sides are built from it), the bottom's its
  // negation (the same terms negated), and each side's (b - a) x that normal, exactly: outward
  // in the polygon's plane (its loop is counter-clockwise about n).
  GaussKind kind;
  int count[3], exponent = 0;
  const Vector3d g = gauss_normal(p.vertices, top, terms, count, kind, exponent);
  if (!(g.dot(n) > 0)) return Status::InvalidMesh;
  if (kind == GaussKind::OnDemand) {
    double local[3 * kMaxGaussTerms];
    const ExactVector x = exact_gauss_normal(top.data(), K, s.px.data(), s.py.data(), s.pz.data(), exponent, local);
    for (int c = 0; c < 3; ++c) terms.insert(terms.end(), x.terms[c], x.terms[c] + (count[c] = x.count[c]));
  }
  set_normal(0, g, count);
  const size_t top_terms = terms.size();
  for (size_t t = 0; t < top_terms; ++t) terms.push_back(-terms[t]);
  set_normal(1, -g, count);
  // (The top's exact normal held apart: the sides append to the terms it lives in.)
  double held_terms[3 * kMaxGaussTerms];
  ExactVector held = s.exact_normal(0, held_terms);
  for (int c = 0, at = 0; c < 3; at += held.count[c++])
    held.terms[c] = std::copy(held.terms[c], held.terms[c] + held.count[c], held_terms + at) - held.count[c];
  for (int k = 0; k < K; ++k) {
    const Vector3d &a = p.vertices[top[k]], &b = p.vertices[top[(k + 1) % K]];
    int side_count[3];
    bool side_exact = true;
    const Vector3d side = gauss_side_normal(a, b, held, terms, side_count, side_exact);
    if (side == Vector3d::Zero()) return Status::InvalidMesh;
    set_normal(2 + k, side, side_count);
  }
  s.cell_vertex.resize(size_t(s.cells)), s.vertex_cell.resize(size_t(V));
  for (int c = 0; c < 2 * K; ++c) s.cell_vertex[c] = top[c % K];
  for (int k = 0; k < K; ++k) s.vertex_cell[top[k]] = k;
  // Cells: k is the top copy of top[k], K + k its bottom copy. Side k's loop is
  // top(k+1) -> top(k) -> bottom(k) -> bottom(k+1), which fixes the arcs' orientation.
  t.arc_u.resize(size_t(s.arcs)), t.arc_v.resize(size_t(s.arcs)), s.dir.resize(size_t(s.arcs));
  const auto set_arc = [&](int e, int u, int v, const Vector3d& d) { t.arc_u[e] = u, t.arc_v[e] = v, s.dir[e] = d; };
  for (int k = 0; k < K; ++k) {
    const int k1 = (k + 1) % K;
    const Vector3d d = p.vertices[top[k1]] - p.vertices[top[k]];
    set_arc(3 * k, k, k1, d);               // top face edge
    set_arc(3 * k + 1, K + k1, K + k, -d);  // bottom face edge
    // The zero-length edge at top[k], from the top copy down: its arc's pole s_k x s_(k-1)
    // points along -n, so -n (times the polygon's width, the scale of the margins) stands
    // for its direction.
    set_arc(3 * k + 2, k, K + k, -extent * n);
  }
  // Loops: top 0..K-1, bottom (K + K-1)..K, side k as above.
  t.loop_start.assign(1, 0), t.loop_cell.clear();
  for (int k = 0; k < K; ++k) t.loop_cell.push_back(k);
  t.loop_start.push_back(K);
  for (int k = K - 1; k >= 0; --k) t.loop_cell.push_back(K + k);
  t.loop_start.push_back(2 * K);
  for (int k = 0; k < K; ++k) {
    const int k1 = (k + 1) % K;
    for (int c : {k1, k, K + k, K + k1}) t.loop_cell.push_back(c);
    t.loop_start.push_back(int(t.loop_cell.size()));
  }
  return Status::Ok;
}

// A solid: its own faces, edges and vertices.
Status prepare_solid(const ConvexPolytope& p, ShapeData& s, Topology& t) {
  const int V = int(p.vertices.size()), F = int(p.faces.size()), E = int(p.edges.size());
  if (V < 4 || F < 4 || V - E + F != 2) return Status::InvalidMesh;
  s.faces = F, s.arcs = E, s.cells = V;
  s.gauss.resize(size_t(F));
  s.gauss_terms.clear(), s.gauss_term_start.assign(1, 0);
  s.gauss_kind.resize(size_t(F)), s.gauss_exponent.resize(size_t(F));
  t.loop_start.assign(1, 0), t.loop_cell.clear();
  for (int f = 0; f < F; ++f) {
    const Face& face = p.faces[f];
    if (!unit(face.normal) || face.loop.size() < 3) return Status::InvalidMesh;
    for (int v : face.loop)
      if (v < 0 || v >= V) return Status::InvalidMesh;
    int count[3];
    const Vector3d g = gauss_normal(p.vertices, face.loop, s.gauss_terms, count, s.gauss_kind[f], s.gauss_exponent[f]);
    if (!(g.dot(face.normal) > 0)) return Status::InvalidMesh;  // a loop against its normal
    s.gauss[f] = g;
    for (int k = 0; k < 3; ++k) s.gauss_term_start.push_back(s.gauss_term_start.back() + count[k]);
    t.loop_cell.insert(t.loop_cell.end(), face.loop.begin(), face.loop.end());
    t.loop_start.push_back(int(t.loop_cell.size()));
  }
  t.arc_u.resize(size_t(E)), t.arc_v.resize(size_t(E)), s.dir.resize(size_t(E));
  for (int e = 0; e < E; ++e) {
    const Edge& x = p.edges[e];
    if (x.v0 < 0 || x.v0 >= V || x.v1 < 0 || x.v1 >= V || x.v0 == x.v1) return Status::InvalidMesh;
    t.arc_u[e] = x.v0, t.arc_v[e] = x.v1;
    s.dir[e] = p.vertices[x.v1] - p.vertices[x.v0];  // (convex at the edge: checked on the poles)
  }
  s.cell_vertex.resize(size_t(V)), s.vertex_cell.resize(size_t(V));
  for (int v = 0; v < V; ++v) s.cell_vertex[v] = s.vertex_cell[v] = v;
  return Status::Ok;
}

// One orientation's layout from the arcs and the face loops (reversed: the layout of -B, each
// loop read backwards). Each loop step a -> b is an arc whose L (a = u) or R (a = v) is the
// face; at cell a, that arc is followed counter-clockwise by the face and then by the arc of
// the loop's previous step, which orders every cell's slots.
Status build_layout(const Topology& t, int cells, bool reversed, MapLayout& m, std::vector<int>& scratch) {
  // (Raw pointers throughout: a store through one vector's data would make the compiler reload
  // every other vector's, and this runs on every sum of unprepared polytopes.)
  const int E = int(t.arc_u.size()), F = int(t.loop_start.size()) - 1;
  const int *arc_u = t.arc_u.data(), *arc_v = t.arc_v.data();
  m.arc.resize(size_t(E));
  MapLayout::Arc* arc = m.arc.data();
  for (int e = 0; e < E; ++e) arc[e] = {arc_u[e], arc_v[e], -1, -1};
  m.cell_start.assign(size_t(cells) + 1, 0);
  int* cell_start = m.cell_start.data();
  for (int e = 0; e < E; ++e) ++cell_start[arc_u[e] + 1], ++cell_start[arc_v[e] + 1];
  for (int c = 0; c < cells; ++c) cell_start[c + 1] += cell_start[c];
  const int S = 2 * E;
  // Unordered slots: scratch[0, S) their (signed) arcs, [S, 2S) the cells across them, [2S, 3S)
  // successors, [3S, 4S) faces, then each arc's slot at u and at v, then per-cell fill.
  scratch.assign(size_t(4 * S + 2 * E + cells), -1);
  int *arc_of = scratch.data(), *across = arc_of + S, *succ = across + S, *face = succ + S, *at_u = face + S,
      *at_v = at_u + E, *fill = at_v + E;
  std::copy(cell_start, cell_start + cells, fill);
  for (int e = 0; e < E; ++e) {
    const int su = at_u[e] = fill[arc_u[e]]++, sv = at_v[e] = fill[arc_v[e]]++;
    arc_of[su] = e, across[su] = arc_v[e];
    arc_of[sv] = ~e, across[sv] = arc_u[e];
  }
  m.loop_start = t.loop_start;
  const size_t L = t.loop_cell.size();
  m.loop_cell.resize(L), m.loop_arc.resize(L), m.loop_face.resize(L), m.loop_slot.resize(L),
      m.loop_least.resize(size_t(F));
  const int *loop_start = t.loop_start.data(), *in_cell = t.loop_cell.data();
  int *loop_cell = m.loop_cell.data(), *loop_arc = m.loop_arc.data(), *loop_slot = m.loop_slot.data();
  for (int f = 0; f < F; ++f) {
    const int first = loop_start[f], n = loop_start[f + 1] - first;
    for (int k = 0; k < n; ++k) loop_cell[first + k] = in_cell[first + (reversed ? n - 1 - k : k)];
    for (int k = 0; k < n; ++k) {
      const int a = loop_cell[first + k], b = loop_cell[first + (k + 1 < n ? k + 1 : 0)];
      if (a < 0 || a >= cells || b < 0 || b >= cells) return Status::InvalidMesh;
      int found = cell_start[a];
      while (found < cell_start[a + 1] && across[found] != b) ++found;
      if (found == cell_start[a + 1] || face[found] >= 0) return Status::InvalidMesh;  // no such edge, or used twice
      face[found] = f;
      const int e = arc_of[found] >= 0 ? arc_of[found] : ~arc_of[found];
      (arc_of[found] >= 0 ? arc[e].L : arc[e].R) = f;
      loop_arc[first + k] = e, loop_slot[first + k] = found;
    }
    for (int k = 0; k < n; ++k) {
      // At cell k, the previous step's arc: its slot there (cell k is that arc's other end).
      const int prev = loop_arc[first + (k > 0 ? k - 1 : n - 1)], c = loop_cell[first + k];
      succ[loop_slot[first + k]] = arc_u[prev] == c ? at_u[prev] : at_v[prev];
    }
  }
  // Every slot has its face and successor; each cell's slots form one cycle.
  m.cell_slot.resize(size_t(S));
  m.slot_twin.assign(size_t(S), -1);
  int* order = m.slot_twin.data();  // (reused: old slot -> new slot, then the twins)
  for (int c = 0; c < cells; ++c) {
    const int begin = cell_start[c], end = cell_start[c + 1];
    if (end - begin < 3) return Status::InvalidMesh;
    int s = begin;
    for (int k = begin; k < end; ++k) {
      if (s < begin || s >= end || order[s] >= 0 || face[s] < 0) return Status::InvalidMesh;
      order[s] = k;
      s = succ[s];
    }
    if (s != begin) return Status::InvalidMesh;
  }
  MapLayout::Slot* cell_slot = m.cell_slot.data();
  for (int s = 0; s < S; ++s) cell_slot[order[s]] = {arc_of[s], across[s], face[s]};
  for (size_t k = 0; k < L; ++k) loop_slot[k] = order[loop_slot[k]];
  m.arc_slot.resize(size_t(S));
  int* arc_slot = m.arc_slot.data();
  for (int e = 0; e < E; ++e)
    at_u[e] = arc_slot[2 * e] = order[at_u[e]], at_v[e] = arc_slot[2 * e + 1] = order[at_v[e]];
  for (int e = 0; e < E; ++e) order[at_u[e]] = at_v[e], order[at_v[e]] = at_u[e];
  int* loop_face = m.loop_face.data();
  for (int f = 0; f < F; ++f)
    for (int k = loop_start[f]; k < loop_start[f + 1]; ++k) {
      const MapLayout::Arc& x = arc[loop_arc[k]];
      loop_face[k] = x.L == f ? x.R : x.L;
    }
  for (int e = 0; e < E; ++e)
    if (arc[e].L < 0 || arc[e].R < 0 || arc[e].L == arc[e].R) return Status::InvalidMesh;
  return Status::Ok;
}

// Convex at every edge (each pole along its edge; a prism's zero-length edges: along -normal)
// and at every vertex (each cell's corners turn counter-clockwise, exactly).
Status check_map(ShapeData& s) {
  const MapLayout& m = s.map[0];
  const auto g = [&s](int f) { return s.gauss[f]; };
  s.pole_slack = 0;
  double local[3][3 * kMaxGaussTerms];
  for (int e = 0; e < s.arcs; ++e) {
    const int L = m.arc[e].L, R = m.arc[e].R;
    const Vector3d c = g(L).cross(g(R));
    // A short arc (faces that nearly coincide: the exact hull of rounded points keeps them
    // apart) has a rounded pole that is noise: its sign comes from the exact normals, and its
    // angle to the edge is that rounding (pole_error), not a tolerance of the faces.
    if (pole_error_bound(g(L), g(R), c) > 1e-8) {
      if (orient_exact(exact_vector(s.dir[e]), s.exact_normal(L, local[0]), s.exact_normal(R, local[1])) <= 0)
        return Status::InvalidMesh;
      continue;
    }
    if (!(s.dir[e].dot(c) > 0)) return Status::InvalidMesh;
    s.pole_slack = std::max(s.pole_slack, s.dir[e].normalized().cross(c.normalized()).norm());
  }
  for (int c = 0; c < s.cells; ++c) {
    const int begin = m.cell_start[c], n = m.cell_start[c + 1] - begin;
    for (int k = 0; k < n; ++k) {
      const int f0 = m.cell_slot[begin + (k + n - 1) % n].face, f1 = m.cell_slot[begin + k].face,
                f2 = m.cell_slot[begin + (k + 1) % n].face;
      int turn = 0;
      if (!s.rounded_normal(f0) && !s.rounded_normal(f1) && !s.rounded_normal(f2))
        turn = orient(g(f0), g(f1), g(f2));
      else if (!(turn = orient_rounded_filter(g(f0), g(f1), g(f2))))
        turn = orient_exact(s.exact_normal(f0, local[0]), s.exact_normal(f1, local[1]), s.exact_normal(f2, local[2]));
      if (turn <= 0) return Status::InvalidMesh;
    }
  }
  return Status::Ok;
}

}  // namespace

Status prepare(const ConvexPolytope& p, ShapeData& s, bool negated_layout) {
  thread_local Topology topology;
  thread_local std::vector<int> scratch;
  static std::atomic<std::uint64_t> last_id{0};  // (lock-free; preparation is off the real-time path)
  s.id = ++last_id;
  s.polytope_ref = &p;
  double extent = 0;
  if (!take_vertices(p, s, extent)) return Status::InvalidMesh;
  const Status built = p.flat ? prepare_flat(p, s, extent, topology) : prepare_solid(p, s, topology);
  if (built != Status::Ok) return built;
  for (int r = 0; r < 1 + negated_layout; ++r)
    if (build_layout(topology, s.cells, r == 1, s.map[r], scratch) != Status::Ok) return Status::InvalidMesh;
  // The faces the loops give each edge are the ones it lists (the Edge contract).
  if (!p.flat)
    for (int e = 0; e < s.arcs; ++e)
      if (s.map[0].arc[e].L != p.edges[e].left || s.map[0].arc[e].R != p.edges[e].right) return Status::InvalidMesh;
  s.any_rounded = std::any_of(s.gauss_kind.begin(), s.gauss_kind.end(), [](GaussKind k) { return k != GaussKind::Exact; });
  // (A map that fails where a coordinate is under kTinyComponent of the largest: its Gauss
  // normals flushed components that the exact hull kept, so nearly coplanar faces read as
  // coplanar. Beyond the exact predicates' range, not an invalid mesh.)
  if (check_map(s) != Status::Ok) return tiny_coordinates(s) ? Status::OutOfRange : Status::InvalidMesh;
  // Per face, where its loop has its smallest vertex: the sums' loops start there.
  for (int r = 0; r < 1 + negated_layout; ++r)
    for (int f = 0; f < s.faces; ++f) {
      MapLayout& m = s.map[r];
      const int first = m.loop_start[f], n = m.loop_start[f + 1] - first;
      int least = 0;
      for (int k = 1; k < n; ++k)
        if (s.cell_vertex[m.loop_cell[first + k]] < s.cell_vertex[m.loop_cell[first + least]]) least = k;
      m.loop_least[f] = least;
    }
  // The poles in the body frame: a sum whose operands are not turned against each other reads
  // them as they are (-B's are -G_R x -G_L, the negation of the shape's, exactly).
  for (auto& c : s.pole) c.resize(size_t(s.arcs));
  s.pole_zero.resize(size_t(s.arcs)), s.gauss_nonzero.resize(size_t(s.faces));
  for (int f = 0; f < s.faces; ++f) s.gauss_nonzero[f] = nonzero_mask(s.gauss[f]);
  for (int e = 0; e < s.arcs; ++e) {
    const MapLayout::Arc& a = s.map[0].arc[e];
    s.pole[0][e] = s.gauss[a.L].cross(s.gauss[a.R]), s.pole[1][e] = -s.pole[0][e];
    s.pole_zero[e] = pole_zero_mask(s.gauss_nonzero[a.L], s.gauss_nonzero[a.R]);
  }
  s.ex.resize(size_t(s.arcs)), s.ey.resize(size_t(s.arcs)), s.ez.resize(size_t(s.arcs));
  for (int e = 0; e < s.arcs; ++e) {
    const int u = s.cell_vertex[s.map[0].arc[e].u], v = s.cell_vertex[s.map[0].arc[e].v];
    s.ex[e] = s.px[v] - s.px[u], s.ey[e] = s.py[v] - s.py[u], s.ez[e] = s.pz[v] - s.pz[u];
  }
  s.support_error = s.pole_error = 0;
  for (int e = 0; e < s.arcs; ++e) {
    const MapLayout::Arc& a = s.map[0].arc[e];
    const double d = std::sqrt(s.ex[e] * s.ex[e] + s.ey[e] * s.ey[e] + s.ez[e] * s.ez[e]);
    const double angle = pole_error_bound(s.gauss[a.L], s.gauss[a.R], s.pole[0][e]);
    s.pole_error = std::max(s.pole_error, angle);
    if (d > 0) s.support_error = std::max(s.support_error, angle * d);
  }
  s.nx.resize(size_t(s.faces)), s.ny.resize(size_t(s.faces)), s.nz.resize(size_t(s.faces));
  for (int f = 0; f < s.faces; ++f) {
    const Vector3d n = s.gauss[f].normalized();
    s.nx[f] = n.x(), s.ny[f] = n.y(), s.nz[f] = n.z();
  }
  return Status::Ok;
}

}  // namespace detail

namespace {
// An empty shape's polytope, built with the program (a function-local static would register
// its destructor on first use, an allocation inside the first real-time call).
const ConvexPolytope kEmptyPolytope;
}  // namespace

const ConvexPolytope& ConvexShape::polytope() const { return data_ ? *data_->polytope_ref : kEmptyPolytope; }

namespace {

// Takes a built polytope into a new shape.
Status adopt(Status built, ConvexPolytope&& p, ConvexShape& out, const Box* box = nullptr,
             const Triangle* triangle = nullptr) {
  out = ConvexShape{};
  if (built != Status::Ok) return built;
  auto data = std::make_shared<detail::ShapeData>();
  data->polytope = std::move(p);
  if (box) data->kind = detail::ShapeData::Kind::Box, data->box = *box;
  if (triangle) data->kind = detail::ShapeData::Kind::Triangle, data->triangle = *triangle;
  if (const Status s = detail::prepare(data->polytope, *data); s != Status::Ok) return s;
  data->dir = {};  // (prepare's: the edges' directions, checked against the poles)
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
  return adopt(s, std::move(p), out, &box);
}

Status shape_from_triangle(const Triangle& t, ConvexShape& out) {
  ConvexPolytope p;
  const Status s = polytope_from_triangle(t, p);
  return adopt(s, std::move(p), out, nullptr, &t);
}

Status shape_from_polytope(const ConvexPolytope& p, ConvexShape& out) {
  return adopt(Status::Ok, ConvexPolytope(p), out);
}

namespace {

// A radius r of a sphere or capsule: positive, finite, within [kMinExtent, kMaxCoordinate].
Status check_radius(double r) {
  if (!(r > 0) || !std::isfinite(r)) return Status::InvalidArgument;
  return r >= kMinExtent && r <= kMaxCoordinate ? Status::Ok : Status::OutOfRange;
}

// A point or segment core (its vertices alone; see ShapeData::Kind) swept by r.
void adopt_core(std::vector<Vector3d> vertices, double r, ConvexShape& out) {
  auto data = std::make_shared<detail::ShapeData>();
  data->kind = vertices.size() == 1 ? detail::ShapeData::Kind::Point : detail::ShapeData::Kind::Segment;
  data->polytope.vertices = std::move(vertices);
  data->polytope_ref = &data->polytope;
  double extent;
  detail::take_vertices(data->polytope, *data, extent);
  detail::ShapeAccess::set(std::move(data), out);
  detail::ShapeAccess::set_radius(out, r);
}

}  // namespace

Status shape_from_sphere(double radius, ConvexShape& out) {
  out = ConvexShape{};
  if (const Status s = check_radius(radius); s != Status::Ok) return s;
  adopt_core({Vector3d::Zero()}, radius, out);
  return Status::Ok;
}

Status shape_from_capsule(double half_length, double radius, ConvexShape& out) {
  out = ConvexShape{};
  if (!(half_length >= 0) || !std::isfinite(half_length)) return Status::InvalidArgument;
  if (const Status s = check_radius(radius); s != Status::Ok) return s;
  if (half_length == 0) return shape_from_sphere(radius, out);
  if (half_length < kMinExtent || half_length > kMaxCoordinate) return Status::OutOfRange;
  adopt_core({Vector3d(0, 0, -half_length), Vector3d(0, 0, half_length)}, radius, out);
  return Status::Ok;
}

Status shape_with_radius(const ConvexShape& core, double radius, ConvexShape& out) {
  if (core.empty()) return out = ConvexShape{}, Status::TooFewPoints;
  if (!(radius >= 0) || !std::isfinite(radius)) return out = ConvexShape{}, Status::InvalidArgument;
  const double total = core.radius() + radius;
  if (!(total <= kMaxCoordinate)) return out = ConvexShape{}, Status::OutOfRange;
  out = core;
  detail::ShapeAccess::set_radius(out, total);
  return Status::Ok;
}

}  // namespace minksum
