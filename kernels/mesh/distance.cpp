// Mesh-mesh distance through octrees of cubes (the paper's Section 5.1), exact: the octree
// prunes with lower bounds only, and every triangle pair that could hold the closest points gets
// the exact triangle-triangle distance. The search in stages: NodeBounds (a lower bound per node
// pair), PairQueue (the order node pairs are visited in), Search::leaf_pair (the triangles of two
// leaves) and Search::split (a node pair's children).
#include "mesh/mesh_internal.hpp"

#include "query/cache_kinds.hpp"
#include "query/triangle_pairs.hpp"
#include <minksum/kernels.hpp>
#include <minksum/query.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace minksum {

using detail::MeshScratch;
using Eigen::Vector3d;

namespace {

using Entry = MeshScratch::Entry;
using Node = Octree::Node;

// A lower bound of the distance between a triangle (plane n . x = n . p, n unit or zero) and
// the points q: how far they all are on one side of its plane (0 if they straddle it).
double plane_gap(const Vector3d& n, const Vector3d& p, const Vector3d (&q)[3]) {
  const double d0 = n.dot(q[0] - p), d1 = n.dot(q[1] - p), d2 = n.dot(q[2] - p);
  return std::max({std::min({d0, d1, d2}), -std::max({d0, d1, d2}), 0.0});
}

// Lower bounds of the squared distance of two nodes' contents, B placed in A's frame by one
// pose. Topological invariance (Section 4): every box of B has the rotation R in A's frame, so
// all node pairs share the 15 separating axes (A's axes e_i, B's R_j, and the crosses
// e_i x R_j) and each axis's support widths per unit half extent, |L . e_i| and |L . R_j|: one
// table per query, then O(15) per node pair. The bound is the largest of: their boxes apart
// along A's axes (B's box inside its bounding box in A's frame) or B's, along a cross axis, and
// each slab apart from the other's box.
// Why each is a lower bound: a node's triangles lie in its box and its slab (fit_bounds, whole
// triangles); for sets X in box P and Y in box Q, and any unit axis L, every x - y has
// |L . (x - y)| >= (gap of the projections of P and Q on L), so the distance is at least that
// gap (the separating-axis gap); along the boxes' own axes the gaps of all three axes add in
// quadrature, since x - y then has each coordinate at least its gap. A slab is the set
// lo <= n . x <= hi: projections on n again. Rounding: boxes and slabs are padded by 1e-12 of
// their coordinates (fit_bounds), more than the error of these few products.
class NodeBounds {
 public:
  NodeBounds(const Octree& a, const Octree& b, const detail::Rigid& pose)
      : a_(a), b_(b), R_(pose.R), absR_(R_.cwiseAbs()), t_(pose.t) {
    for (int k = 0; k < 9; ++k) {
      const Vector3d axis = Vector3d::Unit(k / 3).cross(R_.col(k % 3));
      const double len = axis.norm();
      if (len < 1e-6) continue;  // nearly parallel axes: no reliable direction (a zero row)
      const Vector3d L = axis / len, LR = (R_.transpose() * L).cwiseAbs();
      for (int d = 0; d < 3; ++d) L_[d][k] = L[d], wa_[d][k] = std::abs(L[d]), wb_[d][k] = LR[d];
    }
  }

  /// The bound for node i of A and node j of B; once it reaches best2 it may be looser (the
  /// pair is pruned either way).
  double operator()(int i, int j, double best2) const {
    const Node &na = a_.nodes[i], &nb = b_.nodes[j];
    const Eigen::Matrix3d& R = R_;
    const Vector3d delta = R * nb.box_center + t_ - na.box_center;
    const Vector3d ga = (delta.cwiseAbs() - na.box_half - absR_ * nb.box_half).cwiseMax(0.0);
    const Vector3d gb =
        ((R.transpose() * delta).cwiseAbs() - nb.box_half - absR_.transpose() * na.box_half).cwiseMax(0.0);
    // Slab of A against B's box: B's box spans normal . (centre) +- |R^T normal| . half.
    const Vector3d nab = R.transpose() * na.normal;
    const double cb = na.normal.dot(R * nb.box_center + t_), rb = nab.cwiseAbs().dot(nb.box_half);
    const double sa = std::max({cb - rb - na.slab_hi, na.slab_lo - cb - rb, 0.0});
    // Slab of B against A's box, in B's frame.
    const Vector3d nba = R * nb.normal;
    const double ca = nba.dot(na.box_center - t_), ra = nba.cwiseAbs().dot(na.box_half);
    const double sb = std::max({ca - ra - nb.slab_hi, nb.slab_lo - ca - ra, 0.0});
    // And along the line between the boxes' centres, the direction that nearly separates them
    // when they are far apart (the 15 fixed axes may miss it by tens of degrees, a bound short
    // by ~10 % of the distance): projections on u = delta / |delta| are centre +- the box's
    // support, so the gap is (|delta|^2 - reach) / |delta|, reach = |delta| . h_a + |R^T delta| . h_b.
    const double len2 = delta.squaredNorm();
    const double reach = delta.cwiseAbs().dot(na.box_half) + (R.transpose() * delta).cwiseAbs().dot(nb.box_half);
    // (gap (gap / len2), not gap^2 / len2: gap^2 overflows where the boxes are 1e77 apart,
    // and an infinite bound pruned every pair: a distance of inf.)
    const double gap = len2 - reach, line = gap > 0 ? gap * (gap / len2) : 0.0;
    const double cheap = std::max({ga.squaredNorm(), gb.squaredNorm(), sa * sa, sb * sb, line});
    if (cheap >= best2) return cheap;  // pruned already: the cross axes cannot matter
    double gx = 0;
    for (int k = 0; k < 9; ++k) {
      const double along = L_[0][k] * delta.x() + L_[1][k] * delta.y() + L_[2][k] * delta.z();
      const double width = wa_[0][k] * na.box_half.x() + wa_[1][k] * na.box_half.y() + wa_[2][k] * na.box_half.z() +
                           wb_[0][k] * nb.box_half.x() + wb_[1][k] * nb.box_half.y() + wb_[2][k] * nb.box_half.z();
      gx = std::max(gx, std::abs(along) - width);
    }
    return std::max(cheap, gx * gx);
  }

 private:
  const Octree &a_, &b_;
  const Eigen::Matrix3d R_, absR_;
  const Vector3d t_;
  double L_[3][9] = {}, wa_[3][9] = {}, wb_[3][9] = {};  // unit cross axes, widths along A's and B's axes (SoA)
};

// The node pairs still to visit. Best first: they leave a heap nearest bound first, so the leaf
// pair that holds the answer is opened before any pair whose bound exceeds it, and `best` is
// tight early (with the answer known from the start, the search costs a fifth on the bunny: the
// loose `best` of a depth-first search opened leaf pairs it did not need). The heap is
// fixed-size: when it is full, it is sorted farthest first and the search goes on depth first
// on that stack (nearest on top), as exact, with a bounded stack (depth_reserve). The heap takes
// what the workspace's stack holds beyond that reserve.
class PairQueue {
 public:
  PairQueue(Entry* storage, size_t heap_pairs) : queue_(storage), heap_pairs_(heap_pairs) {}
  /// Whether the pairs still leave nearest first (else depth first: the rest may be nearer).
  bool best_first() const { return heap_; }
  bool empty() const { return top_ == 0; }
  void push(const Entry& e) {
    if (heap_ && top_ == heap_pairs_) {
      std::sort(queue_, queue_ + top_, farther);
      heap_ = false;
    }
    queue_[top_++] = e;
    if (heap_) std::push_heap(queue_, queue_ + top_, farther);
  }
  Entry pop() {
    if (heap_) std::pop_heap(queue_, queue_ + top_, farther);
    return queue_[--top_];
  }
  /// Whether e would leave next (no queued pair is nearer, or the search is depth first).
  bool leaves_next(const Entry& e) const { return !heap_ || top_ == 0 || farther(queue_[0], e); }

 private:
  // A total order (ties, such as the many bounds of 0 in contact, broken by the nodes): the
  // pairs a seeded search keeps then leave in the cold search's order, so that it opens no pair
  // the cold one does not (while the heap has room). Of tied pairs the deeper leaves first
  // (nodes are numbered breadth first, so the index sum stands in for the depth): in contact it reaches
  // a leaf pair that touches, and best = 0 ends the search, instead of splitting every pair of
  // bound 0 level by level (the contact band's instructions fall 1.1x on the ribbon to 2.9x on
  // the flattened lens; the near and far bands, whose bounds rarely tie, within 4 %).
  static bool farther(const Entry& x, const Entry& y) {
    return x.bound2 != y.bound2 ? x.bound2 > y.bound2 : x.a + x.b != y.a + y.b ? x.a + x.b < y.a + y.b : x.a < y.a;
  }
  Entry* queue_;
  size_t heap_pairs_, top_ = 0;
  bool heap_ = true;
};

// The search of mesh_distance for one pose of B in A's frame. Started from a triangle pair
// (seed), its distance at this pose is the first `best`. Every test prunes with `best`, and a
// smaller best only prunes more, so a seed makes the search visit no more node or triangle
// pairs than the cold one does, but for one thing: triangle pairs wait in a batch of 16 for the
// SIMD kernel, and best drops when a batch is flushed, which a seeded search may reach a few
// pairs later than the cold one (its batches fill slower). So its worst case is the cold
// search's, plus one triangle distance (the seed) and at most one batch of pairs per leaf pair;
// the benchmark Trajectory/bunny_full/minksum_stale_cache shows it on every tick.
class Search {
 public:
  Search(const Octree& a, const Octree& b, const detail::Rigid& pose, MeshScratch& ws, MeshDistance& out)
      : a_(a),
        b_(b),
        pose_(pose),
        ws_(ws),
        out_(out),
        bounds_(a, b, pose),
        clouds_(a.points && b.points) {}

  /// Starts from the triangle pair (seed_a, seed_b) if both index triangles.
  void seed(int seed_a, int seed_b) {
    if (seed_a < 0 || size_t(seed_a) >= a_.triangles.size() || seed_b < 0 || size_t(seed_b) >= b_.triangles.size())
      return;
    Vector3d sa[3], sb[3];
    for (int k = 0; k < 3; ++k)
      sa[k] = a_.vertices[a_.triangles[seed_a][k]], sb[k] = pose_.point(b_.vertices[b_.triangles[seed_b][k]]);
    best_ = triangle_distance(sa, sb, out_.point_a, out_.point_b);
    out_.triangle_a = seed_a, out_.triangle_b = seed_b;
  }

  /// Visits node pairs from the roots until no pair left can be nearer than the best found.
  void run() {
    PairQueue queue(ws_.stack.data(), ws_.stack.size() - detail::depth_reserve(a_, b_));
    queue.push({0, 0, bounds_(0, 0, best_ * best_)});
    out_.stats.node_pairs = 1;
    Entry e{};
    bool next = false;  // e holds the pair to visit next, not yet queued
    while (next || !queue.empty()) {
      if (!next) e = queue.pop();
      next = false;
      if (e.bound2 >= best_ * best_) {  // a nearer pair was found since it was pushed
        if (queue.best_first()) break;  // and the rest are no nearer
        continue;
      }
      const Node &na = a_.nodes[e.a], &nb = b_.nodes[e.b];
      if (na.first_child < 0 && nb.first_child < 0) {
        leaf_pair(na, nb);
        if (best_ == 0) break;  // they intersect: nothing is nearer
        continue;
      }
      next = split(e, na, nb, queue);
    }
    out_.distance = best_;
    out_.intersecting = best_ == 0;
  }

 private:
  // The leaves' separation along the line between their boxes' centres, from their distinct
  // corners (B's projected in B's frame): nearly their distance for two patches facing each
  // other, where boxes and slabs are loose by a leaf's size. Then per triangle (A's highest
  // corner, B's lowest), to prune triangles and pairs behind. (Valid: a triangle is the hull of
  // its corners, so its projection on any line spans its corners' projections; a gap g between
  // the projections on a line of length |axis| means every pair of points is at least g / |axis|
  // apart.)
  struct Line {
    Vector3d axis, axis_b;  // B's box centre - A's, in A's frame and in B's
    double len, shift;      // |axis|; axis . t (B's projections in A's frame are shift + axis_b . x)
    double hi_a, lo_b;      // A's highest corner, B's lowest, along the axis
  };

  void leaf_pair(const Node& na, const Node& nb);
  void first_bound(const Node& na, const Node& nb);
  int near_b(const Node& na, const Node& nb, const Line& line);
  int pass_a(const Node& na, const Node& nb, const Line& line);
  void triangle_pairs(const Node& na, const Line& line, int near, int pass);
  bool split(Entry& e, const Node& na, const Node& nb, PairQueue& queue);
  void flush() {
    pairs_.flush([this](double d, const Vector3d& pa, const Vector3d& pb, int ta, int tb) {
      if (d < best_) best_ = d, out_.point_a = pa, out_.point_b = pb, out_.triangle_a = ta, out_.triangle_b = tb;
    });
  }
  // A triangle's sphere (centre c in the node's own frame) against the node's slab and box.
  bool sphere_near(const Vector3d& c, double r, const Node& n) const {
    const double d = n.normal.dot(c), reach = best_ + r;
    if (d - n.slab_hi >= reach || n.slab_lo - d >= reach) return false;
    return ((c - n.box_center).cwiseAbs() - n.box_half).cwiseMax(0.0).squaredNorm() < reach * reach;
  }
  // Corners x against the slab of `n` whose normal is `normal` in x's frame, `shift` = the
  // normal's offset between the frames.
  bool slab_near(const Vector3d& normal, double shift, const Node& n, const Vector3d (&x)[3]) const {
    const double d0 = normal.dot(x[0]) - shift, d1 = normal.dot(x[1]) - shift, d2 = normal.dot(x[2]) - shift;
    return std::min({d0, d1, d2}) - n.slab_hi < best_ && n.slab_lo - std::max({d0, d1, d2}) < best_;
  }

  const Octree &a_, &b_;
  const detail::Rigid pose_;  // B in A's frame
  MeshScratch& ws_;
  MeshDistance& out_;
  const NodeBounds bounds_;
  const bool clouds_;  // two point clouds: point distances, no triangle kernel
  double best_ = std::numeric_limits<double>::infinity();
  bool first_leaf_pair_ = true;
  detail::TrianglePairs pairs_;  // (in the search, on the stack: no allocation)
};

void Search::first_bound(const Node& na, const Node& nb) {
  // The paper's U: the maximum distance of the first leaf pair (their boxes: they hold the
  // leaves' triangles, which may reach beyond the cubes).
  Box ca, cb;
  ca.center = na.box_center, ca.half_extents = na.box_half;
  cb.center = pose_.point(nb.box_center), cb.rotation = pose_.R, cb.half_extents = nb.box_half;
  Proximity p;
  proximity(ca, cb, p, Want::MaxDistance);
  out_.stats.first_bound = p.max_distance;
  first_leaf_pair_ = false;
}

// Triangles nearer than `best` to the other node's box and slab, pairwise: the sphere distance,
// then the separation along the centre line, then the exact distance. A triangle's sphere is
// tested against the node's box and slab first, then its corners against the slab: exact for
// the flat patches that face each other, where the spheres overlap for every pair. (Valid: a
// triangle lies in its sphere, so its distance to the other node's triangles, which lie in that
// node's box and slab, is at least the sphere's distance to them minus its radius.)
void Search::leaf_pair(const Node& na, const Node& nb) {
  if (first_leaf_pair_) first_bound(na, nb);
  Line line;
  line.axis = pose_.point(nb.box_center) - na.box_center, line.axis_b = pose_.to_body(line.axis);
  line.len = line.axis.norm(), line.shift = pose_.shift(line.axis);
  line.hi_a = -std::numeric_limits<double>::infinity(), line.lo_b = -line.hi_a;
  for (int k = na.corner_first; k < na.corner_first + na.corner_count; ++k)
    line.hi_a = std::max(line.hi_a, line.axis.dot(a_.corners[k]));
  for (int k = nb.corner_first; k < nb.corner_first + nb.corner_count; ++k)
    line.lo_b = std::min(line.lo_b, line.axis_b.dot(b_.corners[k]));
  line.lo_b += line.shift;
  // Pruned where the separation exceeds best * |axis| (NaN while best is infinite and the
  // axis zero: then nothing is pruned; for a zero axis every separation is 0).
  if (line.lo_b - line.hi_a > best_ * line.len) return;
  ++out_.stats.leaf_pairs;
  const int near = near_b(na, nb, line);
  const int pass = near > 0 ? pass_a(na, nb, line) : 0;
  triangle_pairs(na, line, near, pass);
  flush();
}

// B's leaf triangles that pass A's leaf (line, sphere, slab), their corners, normals and spheres
// gathered in A's frame once per leaf pair, not once per triangle pair.
int Search::near_b(const Node& na, const Node& nb, const Line& line) {
  const Vector3d* corners_b = &b_.item_corners[size_t(3) * size_t(nb.first)];
  for (int y = 0; y < nb.count; ++y) {
    const Vector3d* c = corners_b + 3 * y;
    ws_.proj_b[y] = line.shift + std::min({line.axis_b.dot(c[0]), line.axis_b.dot(c[1]), line.axis_b.dot(c[2])});
  }
  int near = 0;
  for (int y = 0; y < nb.count; ++y) {
    if (ws_.proj_b[y] - line.hi_a > best_ * line.len) continue;
    const int tb = b_.items[nb.first + y];
    if (ws_.center_stamp[tb] != ws_.stamp)
      ws_.center_stamp[tb] = ws_.stamp, ws_.moved_center[tb] = pose_.point(b_.spheres[tb].head<3>());
    const Vector3d& c = ws_.moved_center[tb];
    if (!sphere_near(c, b_.spheres[tb][3], na)) continue;
    const Vector3d* cb = corners_b + 3 * y;
    const Vector3d sb[3] = {pose_.point(cb[0]), pose_.point(cb[1]), pose_.point(cb[2])};
    if (!slab_near(na.normal, 0, na, sb)) continue;
    for (int k = 0; k < 3; ++k) ws_.near_corners[3 * near + k] = sb[k];
    ws_.near_normal[near] = pose_.turn(b_.normals[tb]);
    ws_.near_b[near] = tb, ws_.near_r[near] = b_.spheres[tb][3], ws_.near_lo[near] = ws_.proj_b[y];
    ws_.near_x[near] = c.x(), ws_.near_y[near] = c.y(), ws_.near_z[near] = c.z();
    ++near;
  }
  return near;
}

// A's leaf triangles that pass B's leaf, nearest to B along the line first: a near pair found
// early prunes the rest.
int Search::pass_a(const Node& na, const Node& nb, const Line& line) {
  const Vector3d* corners_a = &a_.item_corners[size_t(3) * size_t(na.first)];
  for (int x = 0; x < na.count; ++x) {
    const Vector3d* c = corners_a + 3 * x;
    ws_.proj_a[x] = std::max({line.axis.dot(c[0]), line.axis.dot(c[1]), line.axis.dot(c[2])});
  }
  const Vector3d slab_b = pose_.turn(nb.normal);  // B's slab normal in A's frame
  const double shift_b = pose_.shift(slab_b);
  int pass = 0;
  for (int x = 0; x < na.count; ++x) {
    if (line.lo_b - ws_.proj_a[x] > best_ * line.len) continue;
    const int ta = a_.items[na.first + x];
    if (!sphere_near(pose_.body_point(a_.spheres[ta].head<3>()), a_.spheres[ta][3], nb)) continue;
    const Vector3d* c = corners_a + 3 * x;
    const Vector3d sa[3] = {c[0], c[1], c[2]};
    if (!slab_near(slab_b, shift_b, nb, sa)) continue;
    ws_.pass_a[pass++] = x;
  }
  std::sort(ws_.pass_a.begin(), ws_.pass_a.begin() + pass, [&](int x, int y) { return ws_.proj_a[x] > ws_.proj_a[y]; });
  return pass;
}

// The pairs of A's passing triangles with B's near ones: cheap bounds, then the exact distance
// in batches.
void Search::triangle_pairs(const Node& na, const Line& line, int near, int pass) {
  const Vector3d* corners_a = &a_.item_corners[size_t(3) * size_t(na.first)];
  for (int p = 0; p < pass && best_ > 0; ++p) {
    const int x = ws_.pass_a[p];
    const double top_a = ws_.proj_a[x];
    if (line.lo_b - top_a > best_ * line.len) break;  // and so are the rest, lower along the line
    const int ta = a_.items[na.first + x];
    const Vector3d ca = a_.spheres[ta].head<3>();
    const double rad_a = a_.spheres[ta][3];
    const Vector3d* ca3 = corners_a + 3 * x;
    const Vector3d sa[3] = {ca3[0], ca3[1], ca3[2]};
    const Vector3d& na_unit = a_.normals[ta];
    // The sphere and projection tests over the whole list first (branch-free, vectorisable),
    // then the rest.
    int hits = 0;
    const double best = best_, along = best * line.len;
    for (int y = 0; y < near; ++y) {
      const double dx = ws_.near_x[y] - ca.x(), dy = ws_.near_y[y] - ca.y(), dz = ws_.near_z[y] - ca.z();
      const double reach = best + rad_a + ws_.near_r[y];
      ws_.hits[hits] = y;
      hits += (dx * dx + dy * dy + dz * dz < reach * reach) & !(ws_.near_lo[y] - top_a > along);
    }
    for (int h = 0; h < hits; ++h) {
      const int y = ws_.hits[h], tb = ws_.near_b[y];
      if (clouds_) {  // two points: their distance, no triangle kernel (bit-equal to it)
        const double d = (sa[0] - ws_.near_corners[3 * y]).norm();
        ++out_.stats.triangle_pairs;
        if (ws_.seen_a[ta] != ws_.stamp) ws_.seen_a[ta] = ws_.stamp, ++out_.stats.candidates_a;
        if (ws_.seen_b[tb] != ws_.stamp) ws_.seen_b[tb] = ws_.stamp, ++out_.stats.candidates_b;
        if (d < best_)
          best_ = d, out_.point_a = sa[0], out_.point_b = ws_.near_corners[3 * y], out_.triangle_a = ta,
          out_.triangle_b = tb;
        continue;
      }
      const Vector3d sb[3] = {ws_.near_corners[3 * y], ws_.near_corners[3 * y + 1], ws_.near_corners[3 * y + 2]};
      // Separation along the centre line: a lower bound as tight as the triangles are flat
      // (gap >= best |axis|, squared so no root, as gap (gap / |axis|^2) >= best^2: gap^2
      // overflows for triangles 1e77 from the origin, and inf >= inf skipped the pair).
      const Vector3d axis(ws_.near_x[y] - ca.x(), ws_.near_y[y] - ca.y(), ws_.near_z[y] - ca.z());
      const double hi_a = std::max({axis.dot(sa[0]), axis.dot(sa[1]), axis.dot(sa[2])});
      const double lo_b = std::min({axis.dot(sb[0]), axis.dot(sb[1]), axis.dot(sb[2])});
      if (lo_b > hi_a && (lo_b - hi_a) * ((lo_b - hi_a) / axis.squaredNorm()) >= best_ * best_) continue;
      if (plane_gap(na_unit, sa[0], sb) >= best_) continue;
      if (plane_gap(ws_.near_normal[y], sb[0], sa) >= best_) continue;
      if (ws_.seen_a[ta] != ws_.stamp) ws_.seen_a[ta] = ws_.stamp, ++out_.stats.candidates_a;
      if (ws_.seen_b[tb] != ws_.stamp) ws_.seen_b[tb] = ws_.stamp, ++out_.stats.candidates_b;
      ++out_.stats.triangle_pairs;
      // Queued for the batched kernel: the tests above see `best` as of the last flush, never
      // below the final one, so they only prune less.
      if (pairs_.add(sa, sb, ta, tb)) flush();
      if (best_ == 0) break;
    }
  }
}

// Splits the larger cube of pair e (a leaf cannot be split) and queues the children that may be
// nearer than best. True with e the nearest child when it goes on at once: no queued pair is
// nearer, so it would leave the queue next anyway (a push and a pop saved per level).
bool Search::split(Entry& e, const Node& na, const Node& nb, PairQueue& queue) {
  const int i = e.a, j = e.b;
  const bool split_a = nb.first_child < 0 || (na.first_child >= 0 && na.half >= nb.half);
  const Node& parent = split_a ? na : nb;
  std::array<std::pair<double, int>, 8> kids;
  int n = 0;
  for (int c = parent.first_child; c < parent.first_child + parent.child_count; ++c) {
    const double b2 = split_a ? bounds_(c, j, best_ * best_) : bounds_(i, c, best_ * best_);
    ++out_.stats.node_pairs;
    if (b2 < best_ * best_) kids[n++] = {b2, c};
  }
  for (int k = 1; k < n; ++k)  // insertion sort, farthest first (nearest on top when depth first)
    for (int m = k; m > 0 && kids[m - 1] < kids[m]; --m) std::swap(kids[m - 1], kids[m]);  // (bound, node)
  bool next = false;
  if (n > 0) {
    const Entry nearest{split_a ? kids[n - 1].second : i, split_a ? j : kids[n - 1].second, kids[n - 1].first};
    if (queue.leaves_next(nearest)) --n, e = nearest, next = true;
  }
  for (int k = 0; k < n; ++k) queue.push({split_a ? kids[k].second : i, split_a ? j : kids[k].second, kids[k].first});
  return next;
}

// The search of mesh_distance, from the triangle pair (seed_a, seed_b) if both index triangles.
Status search(const Octree& a, const Octree& b, const detail::Rigid& pose, MeshScratch* scratch, MeshDistance& out,
              int seed_a, int seed_b) {
  if (a.nodes.empty() || b.nodes.empty()) return Status::TooFewPoints;
  if (!scratch) return Status::WorkspaceMismatch;  // not a workspace from make_workspace
  MeshScratch& ws = *scratch;
  if (ws.seen_a.size() != a.triangles.size() || ws.seen_b.size() != b.triangles.size() ||
      ws.center_stamp.size() != b.triangles.size() || ws.hits.size() < size_t(b.max_leaf) ||
      ws.near_r.size() < size_t(b.max_leaf) || ws.near_lo.size() < size_t(b.max_leaf) ||
      ws.proj_b.size() < size_t(b.max_leaf) || ws.proj_a.size() < size_t(a.max_leaf) ||
      ws.pass_a.size() < size_t(a.max_leaf) || ws.near_normal.size() < size_t(b.max_leaf) ||
      ws.near_corners.size() < size_t(3 * b.max_leaf) || ws.stack.size() <= detail::depth_reserve(a, b))
    return Status::WorkspaceMismatch;  // a workspace made for other octrees
  if (++ws.stamp == 0) {         // stamps wrapped: forget every old mark
    std::fill(ws.center_stamp.begin(), ws.center_stamp.end(), 0u);
    std::fill(ws.seen_a.begin(), ws.seen_a.end(), 0u);
    std::fill(ws.seen_b.begin(), ws.seen_b.end(), 0u);
    ws.stamp = 1;
  }
  Search s(a, b, pose, ws, out);
  s.seed(seed_a, seed_b);
  s.run();
  out.stats.culled_percent_a = 100.0 * (1 - double(out.stats.candidates_a) / double(a.triangles.size()));
  out.stats.culled_percent_b = 100.0 * (1 - double(out.stats.candidates_b) / double(b.triangles.size()));
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
  detail::Rigid pose;
  if (const Status s = detail::relative_pose(pose_a, pose_b, pose); s != Status::Ok) return s;
  const Status s = search(a, b, pose, ws.scratch(), out, -1, -1);
  if (s == Status::Ok) to_world(pose_a, out);
  return s;
}

Status mesh_distance(const Octree& a, const Eigen::Isometry3d& pose_a, const Octree& b, const Eigen::Isometry3d& pose_b,
                     MeshWorkspace& ws, ProximityCache& cache, MeshDistance& out) {
  using detail::kCacheMesh;
  out = MeshDistance{};
  detail::Rigid pose;
  if (const Status s = detail::relative_pose(pose_a, pose_b, pose); s != Status::Ok) return s;
  const bool seeded = cache.kind == kCacheMesh;
  const Status s = search(a, b, pose, ws.scratch(), out, seeded ? cache.a[0] : -1, seeded ? cache.b[0] : -1);
  if (s == Status::Ok) to_world(pose_a, out);
  ++(seeded && s == Status::Ok ? cache.warm : cache.cold);
  cache.kind = s == Status::Ok && out.triangle_a >= 0 ? kCacheMesh : 0u;
  cache.a[0] = out.triangle_a, cache.b[0] = out.triangle_b;
  return s;
}

}  // namespace minksum
