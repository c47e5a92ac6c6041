// Mesh-mesh distance through octrees of cubes (the paper's Section 5.1), exact: the octree
// prunes with lower bounds only, and every triangle pair that could hold the closest points gets
// the exact triangle-triangle distance.
#include <minksum/mesh.hpp>

#include "core/validate.hpp"
#include "query/cache_kinds.hpp"
#include "query/triangle_pairs.hpp"
#include <minksum/kernels.hpp>
#include <minksum/query.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace minksum {

using Eigen::Vector3d;

namespace detail {

// What a MeshWorkspace holds: the search's node-pair heap and per-triangle marks, and
// mesh_contact's clipped parts, all sized by make_workspace.
struct MeshScratch {
  /// A node pair still to visit, with its squared distance bound.
  struct Entry {
    int a = 0, b = 0;    ///< node of A, node of B
    double bound2 = 0;   ///< lower bound of their squared distance
  };
  /// Node pairs still to visit: a heap of what it holds beyond 8 (depth_a + depth_b) + 16
  /// (make_workspace's heap_pairs), then that reserve for the depth-first fallback.
  std::vector<Entry> stack;
  std::vector<Eigen::Vector3d> moved_center; ///< B's sphere centres in A's frame, on demand
  std::vector<unsigned> center_stamp;        ///< query stamp per triangle of B
  std::vector<unsigned> seen_a, seen_b;      ///< query stamp per candidate triangle
  std::vector<int> near_b;                   ///< triangles of B's leaf near A's leaf
  std::vector<double> near_x, near_y, near_z, near_r;  ///< their spheres (A's frame)
  std::vector<double> near_lo;               ///< their lowest corners along the leaves' line
  std::vector<double> proj_a, proj_b;        ///< per leaf triangle: A's highest, B's lowest corner there
  std::vector<int> pass_a;                   ///< A's leaf triangles near B's leaf, nearest first
  std::vector<Eigen::Vector3d> near_corners; ///< their corners (A's frame), three each
  std::vector<Eigen::Vector3d> near_normal;  ///< their unit normals (A's frame)
  std::vector<int> hits;                     ///< those near one triangle of A
  std::vector<Eigen::Vector3d> parts;        ///< mesh_contact: corners of the parts inside
  std::vector<int> part_start;               ///< mesh_contact: where each part's corners start
  unsigned stamp = 0;                        ///< current query
};

}  // namespace detail

using detail::MeshScratch;

MeshWorkspace::MeshWorkspace() = default;
MeshWorkspace::MeshWorkspace(const MeshWorkspace& other)
    : scratch_(other.scratch_ ? std::make_unique<MeshScratch>(*other.scratch_) : nullptr) {}
MeshWorkspace::MeshWorkspace(MeshWorkspace&& other) noexcept = default;
MeshWorkspace& MeshWorkspace::operator=(const MeshWorkspace& other) {
  if (this != &other) scratch_ = other.scratch_ ? std::make_unique<MeshScratch>(*other.scratch_) : nullptr;
  return *this;
}
MeshWorkspace& MeshWorkspace::operator=(MeshWorkspace&& other) noexcept = default;
MeshWorkspace::~MeshWorkspace() = default;

namespace {

// Deepest level an octree may have (the bound of mesh_contact's stack; a cube 2^-20 of the
// root's is far below any leaf the adaptive rule keeps).
constexpr int kDepthCap = 20;

// The node's box (its triangles' bounding box) and its slab along the triangles' area-weighted
// mean normal (any unit normal gives a valid slab; a flat patch a thin one). Both hold the
// node's triangles whole, so every bound of the search holds for whole triangles.
void fit_bounds(const std::vector<Vector3d>& v, const std::vector<std::array<int, 3>>& tris,
                const std::vector<int>& list, Octree::Node& node) {
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo, n = Vector3d::Zero();
  for (int t : list) {
    const auto& x = tris[t];
    for (int k : x) lo = lo.cwiseMin(v[k]), hi = hi.cwiseMax(v[k]);
    n += (v[x[1]] - v[x[0]]).cross(v[x[2]] - v[x[0]]);
  }
  node.box_center = (lo + hi) / 2;
  node.box_half = ((hi - lo) / 2).cwiseMax(0.0) * (1 + 1e-12) + Vector3d::Constant(1e-15 * (1 + node.center.norm()));
  node.normal = n.norm() > 0 ? Vector3d(n.normalized()) : Vector3d::UnitZ();
  node.slab_lo = std::numeric_limits<double>::infinity(), node.slab_hi = -node.slab_lo;
  for (int t : list)
    for (int k : tris[t]) {
      const double d = node.normal.dot(v[k]);
      node.slab_lo = std::min(node.slab_lo, d), node.slab_hi = std::max(node.slab_hi, d);
    }
  const double pad = 1e-12 * (std::abs(node.slab_lo) + std::abs(node.slab_hi)) + 1e-15;
  node.slab_lo -= pad, node.slab_hi += pad;
}

// The unit normal of a triangle (zero if it is degenerate).
Vector3d unit_normal(const Vector3d (&v)[3]) {
  const Vector3d n = (v[1] - v[0]).cross(v[2] - v[0]);
  const double len = n.norm();
  return len > 0 ? Vector3d(n / len) : Vector3d::Zero();
}

// A lower bound of the distance between a triangle (plane n . x = n . p, n unit or zero) and
// the points q: how far they all are on one side of its plane (0 if they straddle it).
double plane_gap(const Vector3d& n, const Vector3d& p, const Vector3d (&q)[3]) {
  const double d0 = n.dot(q[0] - p), d1 = n.dot(q[1] - p), d2 = n.dot(q[2] - p);
  return std::max({std::min({d0, d1, d2}), -std::max({d0, d1, d2}), 0.0});
}

}  // namespace

size_t Octree::bytes() const {
  return (vertices.capacity() + normals.capacity() + corners.capacity() + item_corners.capacity()) * sizeof(Vector3d) +
         triangles.capacity() * sizeof(triangles[0]) + spheres.capacity() * sizeof(spheres[0]) +
         nodes.capacity() * sizeof(Node) + items.capacity() * sizeof(int);
}

Status build_octree(const std::vector<Vector3d>& vertices,
                    const std::vector<std::array<int, 3>>& triangles, Octree& out,
                    const OctreeOptions& options) {
  out = Octree{};
  if (triangles.empty()) return Status::TooFewPoints;
  if (options.max_depth < -1 || options.max_depth > 24 || options.leaf_size < 1) return Status::InvalidMesh;
  const int max_depth = options.max_depth >= 0 ? options.max_depth : kDepthCap;
  if (const Status s = detail::check_coordinates(vertices.data(), vertices.size()); s != Status::Ok) return s;
  const int nv = int(vertices.size());
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : triangles)
    for (int k : t) {
      if (k < 0 || k >= nv) return Status::InvalidMesh;
      lo = lo.cwiseMin(vertices[k]), hi = hi.cwiseMax(vertices[k]);
    }
  out.vertices = vertices, out.triangles = triangles;
  for (const auto& t : triangles) {  // centroid, farthest corner (rounded up)
    const Vector3d m = (vertices[t[0]] + vertices[t[1]] + vertices[t[2]]) / 3;
    double r = 0;
    for (int k : t) r = std::max(r, (vertices[k] - m).norm());
    out.spheres.emplace_back(m.x(), m.y(), m.z(), r * (1 + 1e-12) + 1e-15 * (m.norm() + r));
    const Vector3d corners[3] = {vertices[t[0]], vertices[t[1]], vertices[t[2]]};
    out.normals.push_back(unit_normal(corners));
  }
  // The root: the bounding cube of the used vertices, a little larger so nothing sits on it.
  const Vector3d center = (lo + hi) / 2;
  const double size = std::max(1.0, center.cwiseAbs().maxCoeff());
  const double root_half = (hi - lo).maxCoeff() / 2 * (1 + 1e-9) + 1e-12 * size;
  // Breadth first, so that every node's children are contiguous.
  std::vector<std::vector<int>> lists(1);
  std::vector<int> level(1, 0);
  // A triangle with exactly the corners of an earlier one is left out of the leaves: it cannot
  // be nearer, and a mesh of many copies would make leaf pairs quadratic in the copies.
  std::vector<std::array<double, 9>> key(triangles.size());
  for (size_t k = 0; k < triangles.size(); ++k) {
    std::array<Vector3d, 3> c = {vertices[triangles[k][0]], vertices[triangles[k][1]], vertices[triangles[k][2]]};
    std::sort(c.begin(), c.end(), [](const Vector3d& x, const Vector3d& y) {
      return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
    });
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d) key[k][3 * i + d] = c[i][d];
  }
  std::vector<int> order(triangles.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return key[x] < key[y]; });
  std::vector<char> copy(triangles.size(), 0);
  for (size_t k = 1; k < order.size(); ++k) copy[order[k]] = key[order[k]] == key[order[k - 1]];
  for (size_t k = 0; k < triangles.size(); ++k)
    if (!copy[k]) lists[0].push_back(int(k));
  out.nodes.emplace_back();
  out.nodes[0].center = center, out.nodes[0].half = root_half;
  for (size_t i = 0; i < out.nodes.size(); ++i) {
    std::vector<int> list = std::move(lists[i]);
    out.depth = std::max(out.depth, level[i]);
    fit_bounds(vertices, triangles, list, out.nodes[i]);
    const auto make_leaf = [&] {
      out.nodes[i].first = int(out.items.size());
      out.nodes[i].count = int(list.size());
      out.items.insert(out.items.end(), list.begin(), list.end());
      for (int t : list)
        for (int k : triangles[t]) out.item_corners.push_back(vertices[k]);
      std::vector<int> used;
      for (int t : list) used.insert(used.end(), triangles[t].begin(), triangles[t].end());
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      out.nodes[i].corner_first = int(out.corners.size());
      out.nodes[i].corner_count = int(used.size());
      for (int k : used) out.corners.push_back(vertices[k]);
      ++out.leaves;
      out.max_leaf = std::max(out.max_leaf, int(list.size()));
    };
    if (int(list.size()) <= options.leaf_size || level[i] >= max_depth) {
      make_leaf();
      continue;
    }
    // Each triangle goes to the child cube that holds its centroid (listed once: a triangle pair
    // is tested in one leaf pair only; the boxes bound whole triangles, so a box may reach
    // beyond its cube). All in one child (a dense patch): the cube narrows in on it, no level
    // is made; 60 halvings are below any double's resolution (identical centroids: a leaf).
    std::vector<int> sub[8];
    for (int tries = 0;; ++tries) {
      const Vector3d c = out.nodes[i].center;
      for (auto& x : sub) x.clear();
      for (int t : list) {
        const Vector3d m = out.spheres[size_t(t)].head<3>();
        sub[(m.x() > c.x()) | (m.y() > c.y()) << 1 | (m.z() > c.z()) << 2].push_back(t);
      }
      const auto full = std::find_if(std::begin(sub), std::end(sub), [&](const auto& x) { return x.size() == list.size(); });
      if (full == std::end(sub) || tries == 60) break;
      const int octant = int(full - std::begin(sub));
      out.nodes[i].half /= 2;
      out.nodes[i].center += out.nodes[i].half * Vector3d(octant & 1 ? 1 : -1, octant & 2 ? 1 : -1, octant & 4 ? 1 : -1);
    }
    if (std::any_of(std::begin(sub), std::end(sub), [&](const auto& x) { return x.size() == list.size(); })) {
      make_leaf();
      continue;
    }
    const Vector3d c = out.nodes[i].center;
    const double h = out.nodes[i].half / 2;
    const int first_child = int(out.nodes.size());
    for (int octant = 0; octant < 8; ++octant) {
      if (sub[octant].empty()) continue;
      out.nodes.emplace_back();
      out.nodes.back().center = c + h * Vector3d(octant & 1 ? 1 : -1, octant & 2 ? 1 : -1, octant & 4 ? 1 : -1);
      out.nodes.back().half = h;
      lists.push_back(std::move(sub[octant]));
      level.push_back(level[i] + 1);
    }
    out.nodes[i].first_child = first_child;
    out.nodes[i].child_count = int(out.nodes.size()) - first_child;
  }
  // The arrays grew by doubling: give back what they do not use (up to half of each).
  out.nodes.shrink_to_fit(), out.items.shrink_to_fit(), out.corners.shrink_to_fit();
  out.item_corners.shrink_to_fit(), out.spheres.shrink_to_fit(), out.normals.shrink_to_fit();
  return Status::Ok;
}

namespace {

// The node pairs of the search wait in a heap (kMeshHeapPairs by default), nearest bound first; past
// that it goes on depth first, where each split pops one pair and pushes at most 8: the stack
// never grows by more than 7 per level of the current path plus one (depth_reserve).
size_t depth_reserve(const Octree& a, const Octree& b) { return size_t(8 * (a.depth + b.depth) + 16); }

}  // namespace

Status build_octree(const std::vector<Vector3d>& points, Octree& out, const OctreeOptions& options) {
  // Nothing in the octree or the search needs an area: a zero-area triangle's box, slab and
  // sphere bound its point, and triangle_distance takes degenerate triangles.
  std::vector<std::array<int, 3>> triangles(points.size());
  for (size_t k = 0; k < points.size(); ++k) triangles[k] = {int(k), int(k), int(k)};
  const Status s = build_octree(points, triangles, out, options);
  out.points = s == Status::Ok;
  return s;
}

void make_workspace(const Octree& a, const Octree& b, MeshWorkspace& workspace, int heap_pairs) {
  if (!workspace.scratch_) workspace.scratch_ = std::make_unique<MeshScratch>();
  MeshScratch& ws = *workspace.scratch_;
  ws.stack.assign(size_t(std::max(heap_pairs, 1)) + depth_reserve(a, b), MeshScratch::Entry{});
  ws.moved_center.assign(b.triangles.size(), Vector3d::Zero());
  ws.center_stamp.assign(b.triangles.size(), 0);
  ws.seen_a.assign(a.triangles.size(), 0);
  ws.seen_b.assign(b.triangles.size(), 0);
  for (auto* v : {&ws.near_b, &ws.hits}) v->assign(size_t(b.max_leaf), 0);
  for (auto* v : {&ws.near_x, &ws.near_y, &ws.near_z, &ws.near_r, &ws.near_lo, &ws.proj_b}) v->assign(size_t(b.max_leaf), 0.0);
  ws.proj_a.assign(size_t(a.max_leaf), 0.0);
  ws.pass_a.assign(size_t(a.max_leaf), 0);
  ws.near_corners.assign(size_t(3 * b.max_leaf), Vector3d::Zero());
  ws.near_normal.assign(size_t(b.max_leaf), Vector3d::Zero());
  ws.parts.assign(size_t(8 * kMaxContactTriangles), Vector3d::Zero());
  ws.part_start.assign(size_t(kMaxContactTriangles + 1), 0);
  ws.stamp = 0;
}

namespace {

// The search of mesh_distance, from the triangle pair (seed_a, seed_b) if both index
// triangles: its distance at this pose is the first `best`. Every test below prunes with
// `best`, and a smaller best only prunes more, so a seed makes the search visit no more node
// or triangle pairs than the cold one (-1, -1) does, but for one thing: triangle pairs wait
// in a batch of 16 for the SIMD kernel, and best drops when a batch is flushed, which a
// seeded search may reach a few pairs later than the cold one (its batches fill slower). So
// its worst case is the cold search's, plus one triangle distance (the seed) and at most one
// batch of pairs per leaf pair; the benchmark Trajectory/bunny_full/minksum_stale_cache
// shows it on every tick.
Status search(const Octree& a, const Octree& b, const Eigen::Isometry3d& pose, MeshScratch* scratch, MeshDistance& out,
              int seed_a, int seed_b) {
  if (a.nodes.empty() || b.nodes.empty()) return Status::TooFewPoints;
  if (!scratch) return Status::InvalidMesh;  // not a workspace from make_workspace
  MeshScratch& ws = *scratch;
  if (ws.seen_a.size() != a.triangles.size() || ws.seen_b.size() != b.triangles.size() ||
      ws.center_stamp.size() != b.triangles.size() ||
      ws.hits.size() < size_t(b.max_leaf) || ws.near_r.size() < size_t(b.max_leaf) ||
      ws.near_lo.size() < size_t(b.max_leaf) || ws.proj_b.size() < size_t(b.max_leaf) || ws.proj_a.size() < size_t(a.max_leaf) || ws.pass_a.size() < size_t(a.max_leaf) ||
      ws.near_normal.size() < size_t(b.max_leaf) || ws.near_corners.size() < size_t(3 * b.max_leaf) || ws.stack.size() <= depth_reserve(a, b))
    return Status::InvalidMesh;  // a workspace made for other octrees
  if (++ws.stamp == 0) {  // stamps wrapped: forget every old mark
    std::fill(ws.center_stamp.begin(), ws.center_stamp.end(), 0u);
    std::fill(ws.seen_a.begin(), ws.seen_a.end(), 0u);
    std::fill(ws.seen_b.begin(), ws.seen_b.end(), 0u);
    ws.stamp = 1;
  }
  const Eigen::Matrix3d R = pose.linear();
  const Vector3d t = pose.translation();
  // Topological invariance (Section 4): every box of B has the rotation R in A's frame, so all
  // node pairs share the 15 separating axes (A's axes e_i, B's R_j, and the crosses e_i x R_j)
  // and each axis's support widths per unit half extent, |L . e_i| and |L . R_j|: one table per
  // query, then O(15) per node pair. Lower bound of the squared distance of two nodes'
  // contents, the largest of: their boxes apart along A's axes (B's box inside its bounding
  // box in A's frame) or B's, along a cross axis, and each slab apart from the other's box.
  // Why each is a lower bound: a node's triangles lie in its box and its slab (fit_bounds, whole
  // triangles); for sets X in box P and Y in box Q, and any unit axis L, every x - y has
  // |L . (x - y)| >= (gap of the projections of P and Q on L), so the distance is at least that
  // gap (the separating-axis gap); along the boxes' own axes the gaps of all three axes add in
  // quadrature, since x - y then has each coordinate at least its gap. A slab is the set
  // lo <= n . x <= hi: projections on n again. Rounding: boxes and slabs are padded by 1e-12 of
  // their coordinates (fit_bounds), more than the error of these few products.
  double best = std::numeric_limits<double>::infinity();
  if (seed_a >= 0 && size_t(seed_a) < a.triangles.size() && seed_b >= 0 && size_t(seed_b) < b.triangles.size()) {
    Vector3d sa[3], sb[3];
    for (int k = 0; k < 3; ++k)
      sa[k] = a.vertices[a.triangles[seed_a][k]], sb[k] = R * b.vertices[b.triangles[seed_b][k]] + t;
    best = triangle_distance(sa, sb, out.point_a, out.point_b);
    out.triangle_a = seed_a, out.triangle_b = seed_b;
  }
  const Eigen::Matrix3d absR = R.cwiseAbs();
  struct CrossAxes {
    double L[3][9], wa[3][9], wb[3][9];  // unit axis, widths along A's and B's axes (SoA)
  } X{};
  for (int k = 0; k < 9; ++k) {
    const Vector3d axis = Vector3d::Unit(k / 3).cross(R.col(k % 3));
    const double len = axis.norm();
    if (len < 1e-6) continue;  // nearly parallel axes: no reliable direction (a zero row)
    const Vector3d L = axis / len, LR = (R.transpose() * L).cwiseAbs();
    for (int d = 0; d < 3; ++d) X.L[d][k] = L[d], X.wa[d][k] = std::abs(L[d]), X.wb[d][k] = LR[d];
  }
  const auto bound2 = [&](int i, int j) {
    const Octree::Node &na = a.nodes[i], &nb = b.nodes[j];
    const Vector3d delta = R * nb.box_center + t - na.box_center;
    const Vector3d ga = (delta.cwiseAbs() - na.box_half - absR * nb.box_half).cwiseMax(0.0);
    const Vector3d gb = ((R.transpose() * delta).cwiseAbs() - nb.box_half - absR.transpose() * na.box_half).cwiseMax(0.0);
    // Slab of A against B's box: B's box spans normal . (centre) +- |R^T normal| . half.
    const Vector3d nab = R.transpose() * na.normal;
    const double cb = na.normal.dot(R * nb.box_center + t), rb = nab.cwiseAbs().dot(nb.box_half);
    const double sa = std::max({cb - rb - na.slab_hi, na.slab_lo - cb - rb, 0.0});
    // Slab of B against A's box, in B's frame.
    const Vector3d nba = R * nb.normal;
    const double ca = nba.dot(na.box_center - t), ra = nba.cwiseAbs().dot(na.box_half);
    const double sb = std::max({ca - ra - nb.slab_hi, nb.slab_lo - ca - ra, 0.0});
    // And along the line between the boxes' centres, the direction that nearly separates them
    // when they are far apart (the 15 fixed axes may miss it by tens of degrees, a bound short
    // by ~10 % of the distance): projections on u = delta / |delta| are centre +- the box's
    // support, so the gap is (|delta|^2 - reach) / |delta|, reach = |delta| . h_a + |R^T delta| . h_b.
    const double len2 = delta.squaredNorm();
    const double reach = delta.cwiseAbs().dot(na.box_half) + (R.transpose() * delta).cwiseAbs().dot(nb.box_half);
    const double line = len2 > reach ? (len2 - reach) * (len2 - reach) / len2 : 0.0;
    const double cheap = std::max({ga.squaredNorm(), gb.squaredNorm(), sa * sa, sb * sb, line});
    if (cheap >= best * best) return cheap;  // pruned already: the cross axes cannot matter
    double gx = 0;
    for (int k = 0; k < 9; ++k) {
      const double along = X.L[0][k] * delta.x() + X.L[1][k] * delta.y() + X.L[2][k] * delta.z();
      const double width = X.wa[0][k] * na.box_half.x() + X.wa[1][k] * na.box_half.y() + X.wa[2][k] * na.box_half.z() +
                           X.wb[0][k] * nb.box_half.x() + X.wb[1][k] * nb.box_half.y() + X.wb[2][k] * nb.box_half.z();
      gx = std::max(gx, std::abs(along) - width);
    }
    return std::max(cheap, gx * gx);
  };
  const bool clouds = a.points && b.points;
  detail::TrianglePairs pairs;  // (on the stack: no allocation)
  const auto flush = [&] {
    pairs.flush([&](double d, const Vector3d& pa, const Vector3d& pb, int ta, int tb) {
      if (d < best) best = d, out.point_a = pa, out.point_b = pb, out.triangle_a = ta, out.triangle_b = tb;
    });
  };
  bool first_leaf_pair = true;
  // Best first: node pairs leave the heap nearest bound first, so the leaf pair that holds the
  // answer is opened before any pair whose bound exceeds it, and `best` is tight early (with
  // the answer known from the start, the search costs a fifth on the bunny: the loose `best`
  // of a depth-first search opened leaf pairs it did not need). The heap is fixed-size: when
  // it is full, it is sorted farthest first and the search goes on depth first on that stack
  // (nearest on top), as exact, with a bounded stack (depth_reserve). The heap takes what the
  // workspace's stack holds beyond that reserve.
  using Entry = MeshScratch::Entry;
  Entry* queue = ws.stack.data();
  // A total order (ties, such as the many bounds of 0 in contact, broken by the nodes): the
  // pairs a seeded search keeps then leave in the cold search's order, so that it opens no
  // pair the cold one does not (while the heap has room).
  const auto farther = [](const Entry& x, const Entry& y) {
    return x.bound2 != y.bound2 ? x.bound2 > y.bound2 : x.a != y.a ? x.a > y.a : x.b > y.b;
  };
  const size_t heap_pairs = ws.stack.size() - depth_reserve(a, b);
  size_t top = 0;
  bool heap = true;
  const auto push = [&](const Entry& e) {
    if (heap && top == heap_pairs) {
      std::sort(queue, queue + top, farther);
      heap = false;
    }
    queue[top++] = e;
    if (heap) std::push_heap(queue, queue + top, farther);
  };
  push({0, 0, bound2(0, 0)});
  out.stats.node_pairs = 1;
  Entry e{};
  bool next = false;  // e holds the pair to visit next, not yet queued
  while (next || top > 0) {
    if (!next) {
      if (heap) std::pop_heap(queue, queue + top, farther);
      e = queue[--top];
    }
    next = false;
    const int i = e.a, j = e.b;
    if (e.bound2 >= best * best) {  // a nearer pair was found since it was pushed
      if (heap) break;              // and the rest are no nearer
      continue;
    }
    const Octree::Node &na = a.nodes[i], &nb = b.nodes[j];
    if (na.first_child < 0 && nb.first_child < 0) {
      if (first_leaf_pair) {  // the paper's U: the maximum distance of the first leaf pair
        Box ca, cb;  // (their boxes: they hold the leaves' triangles, which may reach beyond the cubes)
        ca.center = na.box_center, ca.half_extents = na.box_half;
        cb.center = R * nb.box_center + t, cb.rotation = R, cb.half_extents = nb.box_half;
        Proximity p;
        proximity(ca, cb, p, Want::MaxDistance);
        out.stats.first_bound = p.max_distance;
        first_leaf_pair = false;
      }
      // Triangles nearer than `best` to the other node's box and slab, pairwise: the sphere
      // distance, then the separation along the centre line, then the exact distance. A
      // triangle's sphere (centre c in the node's own frame) is tested against the node's box
      // and slab first, then its corners against the slab: exact for the flat patches that
      // face each other, where the spheres overlap for every pair. (Valid: a triangle lies in
      // its sphere, so its distance to the other node's triangles, which lie in that node's box
      // and slab, is at least the sphere's distance to them minus its radius.)
      const auto sphere_near = [&best](const Vector3d& c, double r, const Octree::Node& n) {
        const double d = n.normal.dot(c), reach = best + r;
        if (d - n.slab_hi >= reach || n.slab_lo - d >= reach) return false;
        return ((c - n.box_center).cwiseAbs() - n.box_half).cwiseMax(0.0).squaredNorm() < reach * reach;
      };
      // Corners x against the slab of `n` whose normal is `normal` in x's frame, `shift` = the
      // normal's offset between the frames.
      const auto slab_near = [&best](const Vector3d& normal, double shift, const Octree::Node& n,
                                     const Vector3d (&x)[3]) {
        const double d0 = normal.dot(x[0]) - shift, d1 = normal.dot(x[1]) - shift, d2 = normal.dot(x[2]) - shift;
        return std::min({d0, d1, d2}) - n.slab_hi < best && n.slab_lo - std::max({d0, d1, d2}) < best;
      };
      // The leaves' separation along the line between their boxes' centres, from their
      // distinct corners (B's projected in B's frame): nearly their distance for two patches
      // facing each other, where boxes and slabs are loose by a leaf's size. Then per
      // triangle (A's highest corner, B's lowest), to prune triangles and pairs behind.
      // (Valid: a triangle is the hull of its corners, so its projection on any line spans
      // its corners' projections; a gap g between the projections on a line of length |axis|
      // means every pair of points is at least g / |axis| apart.)
      const Vector3d axis = R * nb.box_center + t - na.box_center, axis_b = R.transpose() * axis;
      const double axis_len = axis.norm(), shift = axis.dot(t);
      double hi_a = -std::numeric_limits<double>::infinity(), lo_b = -hi_a;
      for (int k = na.corner_first; k < na.corner_first + na.corner_count; ++k) hi_a = std::max(hi_a, axis.dot(a.corners[k]));
      for (int k = nb.corner_first; k < nb.corner_first + nb.corner_count; ++k) lo_b = std::min(lo_b, axis_b.dot(b.corners[k]));
      lo_b += shift;
      // Pruned where the separation exceeds best * |axis| (NaN while best is infinite and the
      // axis zero: then nothing is pruned; for a zero axis every separation is 0).
      if (lo_b - hi_a > best * axis_len) continue;
      ++out.stats.leaf_pairs;
      const Vector3d* corners_a = &a.item_corners[size_t(3) * size_t(na.first)];
      const Vector3d* corners_b = &b.item_corners[size_t(3) * size_t(nb.first)];
      for (int x = 0; x < na.count; ++x) {
        const Vector3d* c = corners_a + 3 * x;
        ws.proj_a[x] = std::max({axis.dot(c[0]), axis.dot(c[1]), axis.dot(c[2])});
      }
      for (int y = 0; y < nb.count; ++y) {
        const Vector3d* c = corners_b + 3 * y;
        ws.proj_b[y] = shift + std::min({axis_b.dot(c[0]), axis_b.dot(c[1]), axis_b.dot(c[2])});
      }
      int near = 0;
      for (int y = 0; y < nb.count; ++y) {
        if (ws.proj_b[y] - hi_a > best * axis_len) continue;
        const int tb = b.items[nb.first + y];
        if (ws.center_stamp[tb] != ws.stamp)
          ws.center_stamp[tb] = ws.stamp, ws.moved_center[tb] = R * b.spheres[tb].head<3>() + t;
        const Vector3d& c = ws.moved_center[tb];
        if (!sphere_near(c, b.spheres[tb][3], na)) continue;
        const Vector3d* cb = corners_b + 3 * y;
        const Vector3d sb[3] = {R * cb[0] + t, R * cb[1] + t, R * cb[2] + t};
        if (!slab_near(na.normal, 0, na, sb)) continue;
        // Corners and unit normal once per leaf pair, not once per triangle pair.
        for (int k = 0; k < 3; ++k) ws.near_corners[3 * near + k] = sb[k];
        ws.near_normal[near] = R * b.normals[tb];
        ws.near_b[near] = tb, ws.near_r[near] = b.spheres[tb][3], ws.near_lo[near] = ws.proj_b[y];
        ws.near_x[near] = c.x(), ws.near_y[near] = c.y(), ws.near_z[near] = c.z();
        ++near;
      }
      const Vector3d slab_b = R * nb.normal;  // B's slab normal in A's frame
      const double shift_b = slab_b.dot(t);
      // A's triangles that pass, nearest to B along the line first: a near pair found early
      // prunes the rest.
      int pass = 0;
      for (int x = 0; x < na.count && near > 0; ++x) {
        if (lo_b - ws.proj_a[x] > best * axis_len) continue;
        const int ta = a.items[na.first + x];
        if (!sphere_near(R.transpose() * (a.spheres[ta].head<3>() - t), a.spheres[ta][3], nb)) continue;
        const Vector3d* ca3 = corners_a + 3 * x;
        const Vector3d sa[3] = {ca3[0], ca3[1], ca3[2]};
        if (!slab_near(slab_b, shift_b, nb, sa)) continue;
        ws.pass_a[pass++] = x;
      }
      std::sort(ws.pass_a.begin(), ws.pass_a.begin() + pass, [&](int x, int y) { return ws.proj_a[x] > ws.proj_a[y]; });
      for (int p = 0; p < pass && best > 0; ++p) {
        const int x = ws.pass_a[p];
        const double top_a = ws.proj_a[x];
        if (lo_b - top_a > best * axis_len) break;  // and so are the rest, lower along the line
        const int ta = a.items[na.first + x];
        const Vector3d ca = a.spheres[ta].head<3>();
        const double rad_a = a.spheres[ta][3];
        const Vector3d* ca3 = corners_a + 3 * x;
        const Vector3d sa[3] = {ca3[0], ca3[1], ca3[2]};
        const Vector3d& na_unit = a.normals[ta];
        // The sphere and projection tests over the whole list first (branch-free,
        // vectorisable), then the rest.
        int hits = 0;
        const double along = best * axis_len;
        for (int y = 0; y < near; ++y) {
          const double dx = ws.near_x[y] - ca.x(), dy = ws.near_y[y] - ca.y(), dz = ws.near_z[y] - ca.z();
          const double reach = best + rad_a + ws.near_r[y];
          ws.hits[hits] = y;
          hits += (dx * dx + dy * dy + dz * dz < reach * reach) & !(ws.near_lo[y] - top_a > along);
        }
        for (int h = 0; h < hits; ++h) {
          const int y = ws.hits[h], tb = ws.near_b[y];
          if (clouds) {  // two points: their distance, no triangle kernel (bit-equal to it)
            const double d = (sa[0] - ws.near_corners[3 * y]).norm();
            ++out.stats.triangle_pairs;
            if (ws.seen_a[ta] != ws.stamp) ws.seen_a[ta] = ws.stamp, ++out.stats.candidates_a;
            if (ws.seen_b[tb] != ws.stamp) ws.seen_b[tb] = ws.stamp, ++out.stats.candidates_b;
            if (d < best) best = d, out.point_a = sa[0], out.point_b = ws.near_corners[3 * y], out.triangle_a = ta, out.triangle_b = tb;
            continue;
          }
          const Vector3d sb[3] = {ws.near_corners[3 * y], ws.near_corners[3 * y + 1], ws.near_corners[3 * y + 2]};
          // Separation along the centre line: a lower bound as tight as the triangles are flat
          // (squared, so no root: gap >= best |axis|).
          const Vector3d axis(ws.near_x[y] - ca.x(), ws.near_y[y] - ca.y(), ws.near_z[y] - ca.z());
          const double hi_a = std::max({axis.dot(sa[0]), axis.dot(sa[1]), axis.dot(sa[2])});
          const double lo_b = std::min({axis.dot(sb[0]), axis.dot(sb[1]), axis.dot(sb[2])});
          if (lo_b > hi_a && (lo_b - hi_a) * (lo_b - hi_a) >= best * best * axis.squaredNorm()) continue;
          if (plane_gap(na_unit, sa[0], sb) >= best) continue;
          if (plane_gap(ws.near_normal[y], sb[0], sa) >= best) continue;
          if (ws.seen_a[ta] != ws.stamp) ws.seen_a[ta] = ws.stamp, ++out.stats.candidates_a;
          if (ws.seen_b[tb] != ws.stamp) ws.seen_b[tb] = ws.stamp, ++out.stats.candidates_b;
          ++out.stats.triangle_pairs;
          // Queued for the batched kernel: the tests above see `best` as of the last flush,
          // never below the final one, so they only prune less.
          if (pairs.add(sa, sb, ta, tb)) flush();
          if (best == 0) break;
        }
      }
      flush();
      if (best == 0) break;  // they intersect: nothing is nearer
      continue;
    }
    // Split the larger cube (a leaf cannot be split), children nearest last so popped first.
    const bool split_a = nb.first_child < 0 || (na.first_child >= 0 && na.half >= nb.half);
    const Octree::Node& parent = split_a ? na : nb;
    std::array<std::pair<double, int>, 8> kids;
    int n = 0;
    for (int c = parent.first_child; c < parent.first_child + parent.child_count; ++c) {
      const double b2 = split_a ? bound2(c, j) : bound2(i, c);
      ++out.stats.node_pairs;
      if (b2 < best * best) kids[n++] = {b2, c};
    }
    for (int k = 1; k < n; ++k)  // insertion sort, farthest first (nearest on top when depth first)
      for (int m = k; m > 0 && kids[m - 1] < kids[m]; --m) std::swap(kids[m - 1], kids[m]);  // (bound, node)
    // The nearest child goes on at once when no queued pair is nearer: it would leave the
    // heap next anyway (a push and a pop saved per level).
    if (n > 0) {
      const Entry nearest{split_a ? kids[n - 1].second : i, split_a ? j : kids[n - 1].second, kids[n - 1].first};
      if (!heap || top == 0 || farther(queue[0], nearest)) --n, e = nearest, next = true;
    }
    for (int k = 0; k < n; ++k) push({split_a ? kids[k].second : i, split_a ? j : kids[k].second, kids[k].first});
  }
  out.distance = best;
  out.intersecting = best == 0;
  out.stats.culled_percent_a = 100.0 * (1 - double(out.stats.candidates_a) / double(a.triangles.size()));
  out.stats.culled_percent_b = 100.0 * (1 - double(out.stats.candidates_b) / double(b.triangles.size()));
  return Status::Ok;
}

}  // namespace

namespace {

// B's placement in A's frame, after both poses are checked: pose_b itself when A sits at the
// identity (no rounding), else pose_a^-1 pose_b.
Status relative_pose(const Eigen::Isometry3d& pose_a, const Eigen::Isometry3d& pose_b, Eigen::Isometry3d& out) {
  if (const Status s = check_pose(pose_a); s != Status::Ok) return s;
  if (const Status s = check_pose(pose_b); s != Status::Ok) return s;
  const bool identity = pose_a.linear() == Eigen::Matrix3d::Identity() && pose_a.translation() == Vector3d::Zero();
  out = identity ? pose_b : Eigen::Isometry3d(pose_a.inverse(Eigen::Isometry) * pose_b);
  return Status::Ok;
}

// A mesh answer's points from A's frame to the world.
void to_world(const Eigen::Isometry3d& pose_a, MeshDistance& out) {
  out.point_a = pose_a * out.point_a, out.point_b = pose_a * out.point_b;
}

}  // namespace

Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const Octree& b, const Eigen::Isometry3d& pose_b,
                     MeshWorkspace& ws, MeshDistance& out) {
  out = MeshDistance{};
  Eigen::Isometry3d pose;
  if (const Status s = relative_pose(pose_a, pose_b, pose); s != Status::Ok) return s;
  const Status s = search(a, b, pose, ws.scratch(), out, -1, -1);
  if (s == Status::Ok) to_world(pose_a, out);
  return s;
}

Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const Octree& b, const Eigen::Isometry3d& pose_b,
                     MeshWorkspace& ws, ProximityCache& cache, MeshDistance& out) {
  using detail::kCacheMesh;
  out = MeshDistance{};
  Eigen::Isometry3d pose;
  if (const Status s = relative_pose(pose_a, pose_b, pose); s != Status::Ok) return s;
  const bool seeded = cache.kind == kCacheMesh;
  const Status s = search(a, b, pose, ws.scratch(), out, seeded ? cache.a[0] : -1, seeded ? cache.b[0] : -1);
  if (s == Status::Ok) to_world(pose_a, out);
  ++(seeded && s == Status::Ok ? cache.warm : cache.cold);
  cache.kind = s == Status::Ok && out.triangle_a >= 0 ? kCacheMesh : 0u;
  cache.a[0] = out.triangle_a, cache.b[0] = out.triangle_b;
  return s;
}

namespace {

// mesh_contact with the tool placed in A's frame by `pose`.
Status contact_in_a(const Octree& a, const ConvexShape& shape, const Eigen::Isometry3d& pose, MeshScratch& ws,
                    MeshContact& out) {
  if (a.nodes.empty() || shape.empty()) return Status::TooFewPoints;
  const ConvexPolytope& tool = shape.polytope();
  const int nv = int(tool.vertices.size());
  if (nv > kMaxToolVertices || tool.flat || nv < 4) return Status::InvalidMesh;
  // The tool in A's frame, and its bounding box there.
  Vector3d v[kMaxToolVertices];
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (int k = 0; k < nv; ++k) {
    v[k] = pose * tool.vertices[k];
    lo = lo.cwiseMin(v[k]), hi = hi.cwiseMax(v[k]);
  }
  const Vector3d box_c = (lo + hi) / 2, box_h = (hi - lo) / 2;
  // The tool's face planes in A's frame. A triangle meets the tool iff clipping it by every
  // plane (Sutherland-Hodgman, 1974) leaves something: O(faces) per triangle.
  const int nf = int(tool.faces.size());
  if (nf > 2 * kMaxToolVertices) return Status::InvalidMesh;
  Vector3d plane_n[2 * kMaxToolVertices];
  double plane_o[2 * kMaxToolVertices];
  alignas(64) double px[2 * kMaxToolVertices], py[2 * kMaxToolVertices], pz[2 * kMaxToolVertices];
  for (int f = 0; f < nf; ++f) {
    plane_n[f] = pose.linear() * tool.faces[f].normal;
    plane_o[f] = tool.faces[f].offset + plane_n[f].dot(pose.translation());
    px[f] = plane_n[f].x(), py[f] = plane_n[f].y(), pz[f] = plane_n[f].z();
  }
  // The part of triangle t inside the tool: `m` corners at `poly` (m = 0: they do not meet).
  // First every plane against the three corners at once (a loop the compiler vectorises):
  // a plane with all corners beyond it rejects the triangle, and only the planes with a
  // corner beyond can cut it; a plane with every corner inside leaves every point of the
  // triangle inside, so clipping by it would change nothing (to rounding).
  Vector3d buffer[2][3 + 2 * kMaxToolVertices];
  alignas(64) double above[2 * kMaxToolVertices], below[2 * kMaxToolVertices];
  int cut[2 * kMaxToolVertices];
  const auto clip = [&](const Vector3d (&t)[3], const Vector3d*& poly) {
    double reject = -1;
    for (int f = 0; f < nf; ++f) {
      const double d0 = px[f] * t[0].x() + py[f] * t[0].y() + pz[f] * t[0].z() - plane_o[f];
      const double d1 = px[f] * t[1].x() + py[f] * t[1].y() + pz[f] * t[1].z() - plane_o[f];
      const double d2 = px[f] * t[2].x() + py[f] * t[2].y() + pz[f] * t[2].z() - plane_o[f];
      above[f] = std::max(std::max(d0, d1), d2), below[f] = std::min(std::min(d0, d1), d2);
    }
    for (int f = 0; f < nf; ++f) reject = std::max(reject, below[f]);
    if (reject > 0) return 0;
    int ncut = 0;
    for (int f = 0; f < nf; ++f) cut[ncut] = f, ncut += above[f] > 0;
    // Sutherland-Hodgman (1974) over the cutting planes.
    int m = 3, cur = 0;
    for (int k = 0; k < 3; ++k) buffer[0][k] = t[k];
    for (int i = 0; i < ncut && m > 0; ++i) {
      const Vector3d& n = plane_n[cut[i]];
      const double o = plane_o[cut[i]];
      int out_m = 0;
      for (int k = 0; k < m; ++k) {
        const Vector3d &p = buffer[cur][k], &q = buffer[cur][(k + 1) % m];
        const double dp = n.dot(p) - o, dq = n.dot(q) - o;
        if (dp <= 0) buffer[1 - cur][out_m++] = p;
        if ((dp < 0 && dq > 0) || (dp > 0 && dq < 0)) buffer[1 - cur][out_m++] = p + dp / (dp - dq) * (q - p);
      }
      m = out_m, cur = 1 - cur;
    }
    poly = buffer[cur];
    return m;
  };
  const auto corners = [&](int tri, Vector3d (&t)[3]) {
    for (int k = 0; k < 3; ++k) t[k] = a.vertices[a.triangles[tri][k]];
  };
  // Pass 1: the overlapped triangles (each once: a triangle is listed in one leaf) and the area
  // vector of their parts inside the tool, whose direction is the push-out direction (a sum over the contact patch: it turns
  // continuously as the tool slides, unlike any single triangle's normal).
  int hit[kMaxContactTriangles], hits = 0;
  ws.part_start[0] = 0;
  Vector3d area = Vector3d::Zero();
  int stack[8 * 25 + 8], top = 0;
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
      corners(tri, t);
      const Vector3d tlo = t[0].cwiseMin(t[1]).cwiseMin(t[2]), thi = t[0].cwiseMax(t[1]).cwiseMax(t[2]);
      if ((tlo.array() > hi.array()).any() || (thi.array() < lo.array()).any()) continue;
      ++out.tested;
      const Vector3d* poly;
      const int m = clip(t, poly);
      if (m == 0) continue;
      if (hits == kMaxContactTriangles || ws.part_start[hits] + m > int(ws.parts.size())) {
        out.overflow = true;  // more contact than capacity: flagged, the first parts count
        continue;
      }
      hit[hits] = tri;
      std::copy(poly, poly + m, ws.parts.begin() + ws.part_start[hits]);
      ws.part_start[hits + 1] = ws.part_start[hits] + m;
      ++hits;
      for (int k = 1; k + 1 < m; ++k) area += (poly[k] - poly[0]).cross(poly[k + 1] - poly[0]) / 2;
    }
  }
  if (hits == 0) return Status::Ok;
  out.intersecting = true;
  Vector3d u = area.norm() > 0 ? Vector3d(area.normalized()) : Vector3d::Zero();
  if (u.isZero()) {  // parts facing both ways cancel (a sheet pinched from both sides)
    Vector3d t[3];
    corners(hit[0], t);
    u = unit_normal(t);
  }
  out.penetration_direction = u;
  // Pass 2: how far the tool must move along u until no part is inside it: for each corner p
  // of the parts, the ray p - lambda u stays in the tool until the first face it leaves by.
  int facing[2 * kMaxToolVertices], nfacing = 0;  // the faces a ray along -u can leave by
  for (int f = 0; f < nf; ++f)
    if (plane_n[f].dot(u) < 0) facing[nfacing++] = f;
  for (int h = 0; h < hits; ++h) {
    for (int k = ws.part_start[h]; k < ws.part_start[h + 1]; ++k) {
      const Vector3d& p = ws.parts[k];
      double lambda = std::numeric_limits<double>::infinity();
      for (int i = 0; i < nfacing; ++i) {
        const int f = facing[i];
        lambda = std::min(lambda, std::max(0.0, plane_o[f] - plane_n[f].dot(p)) / -plane_n[f].dot(u));
      }
      if (std::isfinite(lambda) && (lambda > out.penetration_depth || out.triangle < 0))
        out.penetration_depth = lambda, out.point = p, out.triangle = hit[h];
    }
  }
  return Status::Ok;
}

}  // namespace

Status mesh_contact(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                    const Eigen::Isometry3d& pose_tool, MeshWorkspace& ws, MeshContact& out) {
  out = MeshContact{};
  if (!ws.scratch()) return Status::InvalidMesh;  // not a workspace from make_workspace
  Eigen::Isometry3d pose;
  if (const Status s = relative_pose(pose_a, pose_tool, pose); s != Status::Ok) return s;
  const Status s = contact_in_a(a, shape, pose, *ws.scratch(), out);
  if (out.intersecting) out.penetration_direction = pose_a.linear() * out.penetration_direction;
  if (out.triangle >= 0) out.point = pose_a * out.point;
  return s;
}

}  // namespace minksum
