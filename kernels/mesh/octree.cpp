// The adaptive octree of a mesh or a point cloud (the paper's Section 5.1): cubes split where
// the triangles are dense, each node bounding its triangles whole by a box and a slab.
#include "mesh/mesh_internal.hpp"

#include "core/validate.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>

namespace minksum {

using detail::kDepthCap;
using detail::unit_normal;
using Eigen::Vector3d;

namespace {

// The width of the node's triangles along the unit normal n: [lo, hi] of n . x over their corners.
void slab_along(const std::vector<Vector3d>& v, const std::vector<std::array<int, 3>>& tris,
                const std::vector<int>& list, const Vector3d& n, double& lo, double& hi) {
  lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int t : list)
    for (int k : tris[t]) {
      const double d = n.dot(v[k]);
      lo = std::min(lo, d), hi = std::max(hi, d);
    }
}

// The node's box (its triangles' bounding box) and its slab. The slab's normal is the
// triangles' area-weighted mean normal (it prunes patches that face each other best), unless the
// principal axis of their unoriented normals gives a slab under a quarter as wide: both sheets of
// a thin shell, whose oriented normals cancel. (At a half, ordinary meshes switched more nodes,
// and femur_turbine's near band took 4 % more instructions; at a quarter 0 to 3 nodes of each
// benchmark mesh switch, folds such as an ear.) Any unit normal gives a valid slab; both bounds
// hold the node's triangles whole, so every bound of the search holds for whole triangles.
void fit_bounds(const std::vector<Vector3d>& v, const std::vector<std::array<int, 3>>& tris,
                const std::vector<int>& list, double scale, Octree::Node& node) {
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo, n = Vector3d::Zero();
  Eigen::Matrix3d sheets = Eigen::Matrix3d::Zero();  // sum of area * (unit normal)(unit normal)^T
  for (int t : list) {
    const auto& x = tris[t];
    for (int k : x) lo = lo.cwiseMin(v[k]), hi = hi.cwiseMax(v[k]);
    const Vector3d c = (v[x[1]] - v[x[0]]).cross(v[x[2]] - v[x[0]]);  // twice the area times the normal
    n += c;
    if (const double area = c.norm(); area > 0) sheets += c * c.transpose() / area;
  }
  node.box_center = (lo + hi) / 2;
  node.box_half = ((hi - lo) / 2).cwiseMax(0.0) * (1 + 1e-12) + Vector3d::Constant(1e-15 * (scale + node.center.norm()));
  node.normal = n.norm() > 0 ? Vector3d(n.normalized()) : Vector3d::UnitZ();
  slab_along(v, tris, list, node.normal, node.slab_lo, node.slab_hi);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> shell(sheets);
  const Vector3d axis = shell.eigenvectors().col(2).normalized();  // the largest eigenvalue's
  if (shell.info() == Eigen::Success && axis.allFinite()) {
    double shell_lo, shell_hi;
    slab_along(v, tris, list, axis, shell_lo, shell_hi);
    if (shell_hi - shell_lo < 0.25 * (node.slab_hi - node.slab_lo))
      node.normal = axis, node.slab_lo = shell_lo, node.slab_hi = shell_hi;
  }
  const double pad = 1e-12 * (std::abs(node.slab_lo) + std::abs(node.slab_hi)) + 1e-15 * scale;
  node.slab_lo -= pad, node.slab_hi += pad;
}

}  // namespace

size_t Octree::bytes() const {
  return (vertices.capacity() + normals.capacity() + corners.capacity() + item_corners.capacity()) * sizeof(Vector3d) +
         triangles.capacity() * sizeof(triangles[0]) + spheres.capacity() * sizeof(spheres[0]) +
         nodes.capacity() * sizeof(Node) + items.capacity() * sizeof(int);
}

namespace {

// Per triangle: its bounding sphere (centroid, farthest corner, rounded up) and unit normal.
void triangle_bounds(Octree& out) {
  const auto& v = out.vertices;
  for (const auto& t : out.triangles) {
    const Vector3d m = (v[t[0]] + v[t[1]] + v[t[2]]) / 3;
    double r = 0;
    for (int k : t) r = std::max(r, (v[k] - m).norm());
    out.spheres.emplace_back(m.x(), m.y(), m.z(), r * (1 + 1e-12) + 1e-15 * (m.norm() + r));
    const Vector3d corners[3] = {v[t[0]], v[t[1]], v[t[2]]};
    out.normals.push_back(unit_normal(corners));
  }
}

// The triangles the leaves list: a triangle with exactly the corners of an earlier one is left
// out (it cannot be nearer, and a mesh of many copies would make leaf pairs quadratic in the
// copies).
std::vector<int> distinct_triangles(const Octree& out) {
  const auto& v = out.vertices;
  const auto& tris = out.triangles;
  std::vector<std::array<double, 9>> key(tris.size());
  for (size_t k = 0; k < tris.size(); ++k) {
    std::array<Vector3d, 3> c = {v[tris[k][0]], v[tris[k][1]], v[tris[k][2]]};
    std::sort(c.begin(), c.end(), [](const Vector3d& x, const Vector3d& y) {
      return std::lexicographical_compare(x.data(), x.data() + 3, y.data(), y.data() + 3);
    });
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d) key[k][3 * i + d] = c[i][d];
  }
  std::vector<int> order(tris.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = int(k);
  std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return key[x] < key[y]; });
  std::vector<char> copy(tris.size(), 0);
  for (size_t k = 1; k < order.size(); ++k) copy[order[k]] = key[order[k]] == key[order[k - 1]];
  std::vector<int> list;
  for (size_t k = 0; k < tris.size(); ++k)
    if (!copy[k]) list.push_back(int(k));
  return list;
}

// Node i becomes a leaf of the triangles in `list`: its items, their corners, and its distinct
// corners.
void make_leaf(Octree& out, size_t i, const std::vector<int>& list) {
  out.nodes[i].first = int(out.items.size());
  out.nodes[i].count = int(list.size());
  out.items.insert(out.items.end(), list.begin(), list.end());
  for (int t : list)
    for (int k : out.triangles[t]) out.item_corners.push_back(out.vertices[k]);
  std::vector<int> used;
  for (int t : list) used.insert(used.end(), out.triangles[t].begin(), out.triangles[t].end());
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  out.nodes[i].corner_first = int(out.corners.size());
  out.nodes[i].corner_count = int(used.size());
  for (int k : used) out.corners.push_back(out.vertices[k]);
  ++out.leaves;
  out.max_leaf = std::max(out.max_leaf, int(list.size()));
}

// Each triangle of `list` goes to the child cube of node i that holds its centroid (listed
// once: a triangle pair is tested in one leaf pair only; the boxes bound whole triangles, so a
// box may reach beyond its cube). All in one child (a dense patch): the cube narrows in on it,
// no level is made; 60 halvings are below any double's resolution. False when they cannot be
// parted (identical centroids): the node is a leaf.
bool part(Octree& out, size_t i, const std::vector<int>& list, std::vector<int> (&sub)[8]) {
  for (int tries = 0;; ++tries) {
    const Vector3d c = out.nodes[i].center;
    for (auto& x : sub) x.clear();
    for (int t : list) {
      const Vector3d m = out.spheres[size_t(t)].head<3>();
      sub[(m.x() > c.x()) | (m.y() > c.y()) << 1 | (m.z() > c.z()) << 2].push_back(t);
    }
    const auto full =
        std::find_if(std::begin(sub), std::end(sub), [&](const auto& x) { return x.size() == list.size(); });
    if (full == std::end(sub)) return true;
    if (tries == 60) return false;
    const int octant = int(full - std::begin(sub));
    out.nodes[i].half /= 2;
    out.nodes[i].center += out.nodes[i].half * Vector3d(octant & 1 ? 1 : -1, octant & 2 ? 1 : -1, octant & 4 ? 1 : -1);
  }
}

}  // namespace

Status build_octree(const std::vector<Vector3d>& vertices, const std::vector<std::array<int, 3>>& triangles,
                    Octree& out, const OctreeOptions& options) {
  out = Octree{};
  if (triangles.empty()) return Status::EmptyMesh;
  if (options.max_depth < -1 || options.max_depth > 24 || options.leaf_size < 1) return Status::InvalidArgument;
  const int max_depth = options.max_depth >= 0 ? options.max_depth : kDepthCap;
  if (const Status s = detail::check_coordinates(vertices.data(), vertices.size()); s != Status::Ok) return s;
  const int nv = int(vertices.size());
  Vector3d lo = Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : triangles)
    for (int k : t) {
      if (k < 0 || k >= nv) return Status::InvalidMesh;
      lo = lo.cwiseMin(vertices[k]), hi = hi.cwiseMax(vertices[k]);
    }
  // The root: the bounding cube of the used vertices, a little larger so nothing sits on it.
  // Every margin is relative to the mesh's scale (its extent or its distance from the origin):
  // absolute ones (1e-12, 1e-15) made a mesh 1e-30 across a speck in a box 1e-15 wide, whose
  // sweeps hit at once. Distinct points all under kMinExtent from the origin: products
  // underflow. (A single point, however near, has nothing to underflow.)
  const Vector3d center = (lo + hi) / 2;
  const double extent = (hi - lo).maxCoeff(), scale = std::max(extent, center.cwiseAbs().maxCoeff());
  if (extent > 0 && scale < kMinExtent) return Status::OutOfRange;
  out.vertices = vertices, out.triangles = triangles;
  triangle_bounds(out);
  const double root_half = extent / 2 * (1 + 1e-9) + 1e-12 * scale;
  // Breadth first, so that every node's children are contiguous.
  std::vector<std::vector<int>> lists(1, distinct_triangles(out));
  std::vector<int> level(1, 0);
  out.nodes.emplace_back();
  out.nodes[0].center = center, out.nodes[0].half = root_half;
  for (size_t i = 0; i < out.nodes.size(); ++i) {
    std::vector<int> list = std::move(lists[i]);
    out.depth = std::max(out.depth, level[i]);
    fit_bounds(vertices, triangles, list, scale, out.nodes[i]);
    std::vector<int> sub[8];
    if (int(list.size()) <= options.leaf_size || level[i] >= max_depth || !part(out, i, list, sub)) {
      make_leaf(out, i, list);
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

Status build_octree(const std::vector<Vector3d>& points, Octree& out, const OctreeOptions& options) {
  // Nothing in the octree or the search needs an area: a zero-area triangle's box, slab and
  // sphere bound its point, and triangle_distance takes degenerate triangles.
  std::vector<std::array<int, 3>> triangles(points.size());
  for (size_t k = 0; k < points.size(); ++k) triangles[k] = {int(k), int(k), int(k)};
  const Status s = build_octree(points, triangles, out, options);
  out.points = s == Status::Ok;
  return s;
}

}  // namespace minksum
