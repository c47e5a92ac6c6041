// Exact distance between a convex shape and a mesh (mesh_distance's shape form). A rounded
// shape is its core swept by a ball, so its distance is the core's less the radius: the search
// runs on the core and the bounds grow by the radius, not the triangles. The octree's nodes are
// visited depth first, the nearest bound on top, pruned by lower bounds of their distance to the
// core (its box against the node's box; both projected on the line from the core's nearest
// point to the box's centre; the core against the node's slab); the triangles left get
// the exact distance to the core (PlacedCore::screen, then the batched triangle kernel): a
// point or a segment is one degenerate triangle, a solid core the fans of the faces that can
// hold the nearest point, after a containment test (a triangle inside the solid is nearer than
// the faces say) and a face's certificate (a face resting over the triangle).
#include "mesh/placed_core.hpp"
#include "query/cache_kinds.hpp"
#include "query/triangle_pairs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum {

using Eigen::Vector3d;

namespace {

using detail::PlacedCore;

// The search: the nearest core distance found so far (`best`), its points and triangle.
class ShapeSearch {
 public:
  ShapeSearch(const Octree& a, const PlacedCore& core, double radius, MeshDistance& out)
      : a_(a), core_(core), radius_(radius), out_(out) {}

  // Runs from triangle `seed` (if it indexes one); stops once the cores come within the radius.
  void run(int seed) {
    if (seed >= 0 && seed < int(a_.triangles.size())) {
      Vector3d t[3];
      for (int k = 0; k < 3; ++k) t[k] = a_.vertices[size_t(a_.triangles[size_t(seed)][size_t(k)])];
      seed_ = seed;
      test(seed, t);
      flush();
    }
    struct Entry {
      int node;
      double bound;
    };
    Entry stack[8 * (detail::kDepthCap + 5) + 8];  // depth <= 24: at most 7 more per level
    int top = 0;
    stack[top++] = {0, bound(a_.nodes[0])};
    while (top > 0 && best_ > radius_) {
      const Entry e = stack[--top];
      if (e.bound >= best_) continue;
      const Octree::Node& n = a_.nodes[size_t(e.node)];
      if (n.first_child < 0) {
        leaf(n);
        continue;
      }
      const int first = top;
      for (int c = n.first_child; c < n.first_child + n.child_count; ++c) {
        const double b = bound(a_.nodes[size_t(c)]);
        if (b < best_) stack[top++] = {c, b};
      }
      std::sort(stack + first, stack + top, [](const Entry& x, const Entry& y) { return x.bound > y.bound; });
    }
  }

  double best() const { return best_; }
  const Vector3d& point_mesh() const { return point_mesh_; }
  const Vector3d& point_core() const { return point_core_; }

 private:
  // A lower bound of the core's distance to node n's triangles: the core's box apart from the
  // node's box along A's axes; both apart along the line from the core to the box's centre
  // (their projections on it); and the core apart from the node's slab.
  double bound(const Octree::Node& n) {
    ++out_.stats.node_pairs;
    const Vector3d gap = ((n.box_center - core_.box_c).cwiseAbs() - n.box_half - core_.box_h).cwiseMax(0.0);
    const Vector3d line = n.box_center - core_.nearest(n.box_center);
    const double len = line.norm();
    double across = 0;
    if (len > 0) {
      const Vector3d u = line / len;
      across = u.dot(n.box_center) - u.cwiseAbs().dot(n.box_half) - core_.support(u);
    }
    const double top = core_.support(n.normal), bottom = -core_.support(-n.normal);
    const double slab = std::max(n.slab_lo - top, bottom - n.slab_hi);
    return std::max({gap.norm(), across, slab});
  }

  // The triangles of a leaf that the core's sphere and box may come nearer than `best`.
  void leaf(const Octree::Node& n) {
    ++out_.stats.leaf_pairs;
    for (int x = n.first; x < n.first + n.count && best_ > radius_; ++x) {
      const int tri = a_.items[size_t(x)];
      if (tri == seed_) continue;
      const Eigen::Vector4d& s = a_.spheres[size_t(tri)];
      if ((s.head<3>() - core_.nearest(s.head<3>())).norm() - s[3] - (core_.line ? 0.0 : core_.reach) >= best_) continue;
      const Vector3d* c = &a_.item_corners[3 * size_t(x)];
      const Vector3d lo = c[0].cwiseMin(c[1]).cwiseMin(c[2]), hi = c[0].cwiseMax(c[1]).cwiseMax(c[2]);
      const Vector3d gap = ((core_.box_c - (lo + hi) / 2).cwiseAbs() - (hi - lo) / 2 - core_.box_h).cwiseMax(0.0);
      if (gap.squaredNorm() >= best_ * best_) continue;
      const Vector3d t[3] = {c[0], c[1], c[2]};
      test(tri, t);
    }
    flush();
  }

  // Triangle t's exact distance to the core: proven at once, or queued for the kernel.
  void test(int tri, const Vector3d (&t)[3]) {
    ++out_.stats.candidates_a;
    Vector3d on_t, on_core;
    const double d = core_.screen(t, on_t, on_core, best_, [&](int k) {
      ++out_.stats.triangle_pairs;
      if (pairs_.add(core_.tri[k], t, k, tri)) flush();
    });
    if (d >= 0 && d < best_) best_ = d, point_mesh_ = on_t, point_core_ = on_core, out_.triangle_a = tri;
  }

  void flush() {
    pairs_.flush([&](double d, const Vector3d& ps, const Vector3d& pt, int, int tri) {
      if (d < best_) best_ = d, point_core_ = ps, point_mesh_ = pt, out_.triangle_a = tri;
    });
  }

  const Octree& a_;
  const PlacedCore& core_;
  const double radius_;
  MeshDistance& out_;
  int seed_ = -1;
  double best_ = std::numeric_limits<double>::infinity();
  Vector3d point_mesh_ = Vector3d::Zero(), point_core_ = Vector3d::Zero();
  detail::TrianglePairs pairs_;
};

// The shared body of both forms: `seed` a triangle of A to start from (-1: none).
Status shape_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                      const Eigen::Isometry3d& pose_shape, int seed, MeshDistance& out) {
  out = MeshDistance{};
  detail::Rigid pose;
  if (const Status s = detail::relative_pose(pose_a, pose_shape, pose); s != Status::Ok) return s;
  if (a.nodes.empty() || shape.empty()) return Status::TooFewPoints;
  PlacedCore core;
  if (const Status s = detail::place_core(shape, pose, core); s != Status::Ok) return s;
  const double r = shape.radius();
  ShapeSearch search(a, core, r, out);
  search.run(seed);
  const double d = search.best();
  // Beyond the radius the tool's point lies that far from its core towards the mesh's point;
  // within it, the mesh's point is inside the tool: a point both share.
  out.point_a = search.point_mesh();
  out.intersecting = !(d > r);
  out.distance = out.intersecting ? 0.0 : d - r;
  out.point_b = out.intersecting ? out.point_a
                                 : Vector3d(search.point_core() + r * (search.point_mesh() - search.point_core()) / d);
  out.point_a = pose_a * out.point_a, out.point_b = pose_a * out.point_b;
  out.stats.culled_percent_a = 100.0 * (1 - double(out.stats.candidates_a) / double(a.triangles.size()));
  return Status::Ok;
}

}  // namespace

Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                     const Eigen::Isometry3d& pose_shape, MeshDistance& out) {
  return shape_distance(a, pose_a, shape, pose_shape, -1, out);
}

Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const ConvexShape& shape,
                     const Eigen::Isometry3d& pose_shape, ProximityCache& cache, MeshDistance& out) {
  using detail::kCacheMeshShape;
  const bool seeded = cache.kind == kCacheMeshShape;
  const Status s = shape_distance(a, pose_a, shape, pose_shape, seeded ? cache.a[0] : -1, out);
  ++(seeded && s == Status::Ok ? cache.warm : cache.cold);
  cache.kind = s == Status::Ok && out.triangle_a >= 0 ? kCacheMeshShape : 0u;
  cache.a[0] = out.triangle_a;
  return s;
}

}  // namespace minksum
