// Exact convex hulls of point sets (see hull.hpp): quickhull (Barber, Dobkin and Huhdanpaa, ACM
// TOMS 22(4), 1996) whose every decision is an exact orientation, then the triangles merged
// where exactly coplanar and the points that are no corner dropped from the loops. No tolerance
// anywhere: the facets are those of the exact hull of the doubles given.
#include "core/hull.hpp"

#include "core/expansion.hpp"
#include "core/predicates.hpp"
#include "core/scale.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace minksum::detail {

using Eigen::Vector3d;

int orient3d(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
  // det[b - a; c - a; d - a] from the rounded differences, decided where Shewchuk's error bound
  // for them allows ((7 + 56 eps) eps of the permanent: 1e-15 rounds it up), else exactly: each
  // difference is two doubles (two_diff) and the expansions decide.
  const Vector3d u = b - a, v = c - a, w = d - a;
  const double m0 = v.y() * w.z(), m1 = v.z() * w.y(), m2 = v.z() * w.x(), m3 = v.x() * w.z(), m4 = v.x() * w.y(),
               m5 = v.y() * w.x();
  const double det = u.x() * (m0 - m1) + u.y() * (m2 - m3) + u.z() * (m4 - m5);
  const double perm = std::abs(u.x()) * (std::abs(m0) + std::abs(m1)) + std::abs(u.y()) * (std::abs(m2) + std::abs(m3)) +
                      std::abs(u.z()) * (std::abs(m4) + std::abs(m5));
  if (std::abs(det) > 1e-15 * perm) return det > 0 ? 1 : -1;
  double terms[3][3][2];
  ExactVector x[3];
  const Vector3d* to[3] = {&b, &c, &d};
  for (int r = 0; r < 3; ++r) {
    for (int k = 0; k < 3; ++k) {
      double hi, lo;
      expansion::two_diff((*to[r])[k], a[k], hi, lo);
      int n = 0;  // (increasing magnitude, zeros dropped)
      if (lo != 0) terms[r][k][n++] = lo;
      if (hi != 0) terms[r][k][n++] = hi;
      x[r].terms[k] = terms[r][k], x[r].count[k] = n;
    }
    x[r].sign = 1;
  }
  return orient_exact(x[0], x[1], x[2]);
}

namespace {

// Components below 2^-240 (of the largest, 1 after scaling) read as zero: then every product
// the exact orientation forms stays normal (three factors of 2^-292 or more, and their
// rounding errors: above 2^-1022).
double flushed(double x) { return std::abs(x) < 0x1p-240 ? 0.0 : x; }

// The hull under construction: triangles in flat arrays, each with its three corners (counter-
// clockwise from outside), the triangle across each edge (edge k runs from corner k to k + 1),
// and the points still outside it (a list through next_: no allocation per triangle).
class Quickhull {
 public:
  explicit Quickhull(const std::vector<Vector3d>& p) : p_(p), next_(p.size(), -1) {}

  /// The orientation of points i, j, k, l (orient3d: exact).
  int side(int i, int j, int k, int l) const {
    return orient3d(p_[size_t(i)], p_[size_t(j)], p_[size_t(k)], p_[size_t(l)]);
  }

  bool run() {
    if (!simplex()) return false;
    // One pass: points only ever move to new triangles, which the pass reaches in turn.
    for (int f = 0; f < int(corner_.size()); ++f)
      if (alive_[size_t(f)] && outside_[size_t(f)] >= 0 && !add(f)) return false;
    return true;
  }

  /// The live triangles' corners and neighbours.
  int triangles() const { return int(corner_.size()); }
  bool alive(int f) const { return alive_[size_t(f)]; }
  const std::array<int, 3>& corners(int f) const { return corner_[size_t(f)]; }
  int across(int f, int k) const { return across_[size_t(f)][size_t(k)]; }

 private:
  // Four points spanning a volume: extremes by double distances (they only choose; the exact
  // orientation decides), oriented so that every face looks out. False if none span one.
  bool simplex() {
    const int n = int(p_.size());
    int i0 = 0;
    for (int k = 1; k < n; ++k)
      if (p_[size_t(k)].x() < p_[size_t(i0)].x()) i0 = k;
    const auto farthest = [&](auto score) {
      int best = -1;
      double top = -1;
      for (int k = 0; k < n; ++k)
        if (const double s = score(p_[size_t(k)]); s > top) top = s, best = k;
      return best;
    };
    const Vector3d& a = p_[size_t(i0)];
    const int i1 = farthest([&](const Vector3d& x) { return (x - a).squaredNorm(); });
    const Vector3d& b = p_[size_t(i1)];
    const int i2 = farthest([&](const Vector3d& x) { return (x - a).cross(b - a).squaredNorm(); });
    const Vector3d& c = p_[size_t(i2)];
    const Vector3d normal = (b - a).cross(c - a);
    int i3 = farthest([&](const Vector3d& x) { return std::abs(normal.dot(x - a)); });
    if (i3 < 0 || side(i0, i1, i2, i3) == 0) {  // (rounding hid the volume: any point that has one)
      i3 = -1;
      for (int k = 0; k < n && i3 < 0; ++k)
        if (side(i0, i1, i2, k) != 0) i3 = k;
      if (i3 < 0) return false;
    }
    // Corners (a, b, c) seen from d's side are clockwise when d lies above their plane.
    int v[4] = {i0, i1, i2, i3};
    if (side(i0, i1, i2, i3) > 0) std::swap(v[1], v[2]);
    // Faces of the tetrahedron (v0 v1 v2 v3), each counter-clockwise from outside.
    const int f[4][3] = {{v[0], v[1], v[2]}, {v[0], v[3], v[1]}, {v[1], v[3], v[2]}, {v[2], v[3], v[0]}};
    for (const auto& t : f) make({t[0], t[1], t[2]});
    for (int x = 0; x < 4; ++x)
      for (int k = 0; k < 3; ++k) across_[size_t(x)][size_t(k)] = find_twin(x, k);
    orphans_.clear();
    for (int k = 0; k < n; ++k)
      if (k != v[0] && k != v[1] && k != v[2] && k != v[3]) orphans_.push_back(k);
    assign(0, 4);
    return true;
  }

  // The twin of triangle f's edge k among the first triangles (the simplex's).
  int find_twin(int f, int k) const {
    const int from = corner_[size_t(f)][size_t(k)], to = corner_[size_t(f)][size_t((k + 1) % 3)];
    for (int g = 0; g < int(corner_.size()); ++g)
      for (int j = 0; j < 3; ++j)
        if (corner_[size_t(g)][size_t(j)] == to && corner_[size_t(g)][size_t((j + 1) % 3)] == from) return g;
    return -1;
  }

  int make(const std::array<int, 3>& t) {
    corner_.push_back(t), across_.push_back({-1, -1, -1}), alive_.push_back(true), outside_.push_back(-1);
    mark_.push_back(0);
    return int(corner_.size()) - 1;
  }

  bool above(int f, int point) const {
    const auto& t = corner_[size_t(f)];
    return side(t[0], t[1], t[2], point) > 0;
  }

  // Each orphan to the first of triangles [first, last) it lies strictly outside of; a point
  // outside none lies in the hull (or on it: no corner).
  void assign(int first, int last) {
    for (int q : orphans_)
      for (int f = first; f < last; ++f)
        if (alive_[size_t(f)] && above(f, q)) {
          next_[size_t(q)] = outside_[size_t(f)], outside_[size_t(f)] = q;
          break;
        }
  }

  // Adds the point of f's outside set farthest from its plane (by doubles: it only chooses):
  // the triangles it sees (strictly, exactly) go, and a fan from it to their horizon takes
  // their place, the points they held reassigned to the fan. False if the horizon is no cycle
  // (it always is when every orientation is exact: a guard for coordinates out of range).
  bool add(int f) {
    const auto& t = corner_[size_t(f)];
    const Vector3d n = (p_[size_t(t[1])] - p_[size_t(t[0])]).cross(p_[size_t(t[2])] - p_[size_t(t[0])]);
    int apex = outside_[size_t(f)];
    double far = -std::numeric_limits<double>::infinity();
    for (int q = outside_[size_t(f)]; q >= 0; q = next_[size_t(q)])
      if (const double h = n.dot(p_[size_t(q)] - p_[size_t(t[0])]); h > far) far = h, apex = q;
    // The visible triangles, by a walk across edges from f (they are connected), and the horizon:
    // edges (from, to) of visible triangles whose twin is not visible, with that twin.
    // (Marks are stamps of this step, visible or rim: no clearing, which cost a pass over every
    // triangle ever made at each step.)
    const unsigned visible = stamp_ += 2, rim = visible + 1;
    visible_.assign(1, f), mark_[size_t(f)] = visible;
    horizon_.clear();
    for (size_t i = 0; i < visible_.size(); ++i) {
      const int g = visible_[i];
      for (int k = 0; k < 3; ++k) {
        const int h = across_[size_t(g)][size_t(k)];
        if (mark_[size_t(h)] == visible) continue;
        if (mark_[size_t(h)] != rim && above(h, apex)) {
          mark_[size_t(h)] = visible, visible_.push_back(h);
          continue;
        }
        mark_[size_t(h)] = rim;  // (not visible: a horizon triangle, maybe of several edges)
        horizon_.push_back({corner_[size_t(g)][size_t(k)], corner_[size_t(g)][size_t((k + 1) % 3)], h});
      }
    }
    // The horizon as a cycle: each edge's end is the next edge's start.
    if (!order_horizon()) return false;
    const int first = int(corner_.size());
    for (const Rim& e : horizon_) {
      const int g = make({e.from, e.to, apex});
      across_[size_t(g)][0] = e.beyond;
      const auto& b = corner_[size_t(e.beyond)];
      for (int j = 0; j < 3; ++j)  // (the twin's edge runs to -> from)
        if (b[size_t(j)] == e.to && b[size_t((j + 1) % 3)] == e.from) across_[size_t(e.beyond)][size_t(j)] = g;
    }
    const int m = int(horizon_.size());
    for (int i = 0; i < m; ++i) {  // fan neighbours: edge 1 (to -> apex) meets the next triangle's edge 2
      across_[size_t(first + i)][1] = first + (i + 1) % m;
      across_[size_t(first + (i + 1) % m)][2] = first + i;
    }
    orphans_.clear();
    for (int g : visible_) {
      alive_[size_t(g)] = false;
      for (int q = outside_[size_t(g)]; q >= 0; q = next_[size_t(q)])
        if (q != apex) orphans_.push_back(q);
      outside_[size_t(g)] = -1;
    }
    assign(first, first + m);
    return true;
  }

  // Sorts the horizon's edges into one cycle (from each edge's end to the edge that starts
  // there); false if they form none.
  bool order_horizon() {
    const size_t m = horizon_.size();
    for (size_t i = 0; i + 1 < m; ++i)
      for (size_t j = i + 1; j < m; ++j)
        if (horizon_[j].from == horizon_[i].to) {
          std::swap(horizon_[i + 1], horizon_[j]);
          break;
        }
    for (size_t i = 0; i < m; ++i)
      if (horizon_[i].to != horizon_[(i + 1) % m].from) return false;
    return m >= 3;
  }

  struct Rim {
    int from, to, beyond;
  };
  const std::vector<Vector3d>& p_;
  std::vector<std::array<int, 3>> corner_, across_;
  std::vector<char> alive_;
  std::vector<unsigned> mark_;  // per triangle: the step that saw it visible (even) or on the rim
  unsigned stamp_ = 0;
  std::vector<int> outside_, next_;  // per triangle its first outside point, per point the next
  std::vector<int> visible_, orphans_;
  std::vector<Rim> horizon_;
};

}  // namespace

std::vector<int> planar_hull(const std::vector<Vector3d>& points, const std::vector<int>& ids, const Vector3d& normal) {
  // Projected along the normal's largest axis k: dropping a coordinate is exact, and keeps every
  // orientation of coplanar points (the plane is not parallel to axis k). Andrew's monotone
  // chain (Inf. Proc. Letters 9(5), 1979) on exact orientations: a point on the line through
  // its neighbours, or a duplicate, is no corner.
  int k = 0;
  for (int d = 1; d < 3; ++d)
    if (std::abs(normal[d]) > std::abs(normal[k])) k = d;
  const int i = (k + 1) % 3, j = (k + 2) % 3;  // (i, j, k) cyclic: counter-clockwise about +axis k
  double size = 0;
  for (int id : ids) size = std::max({size, std::abs(points[size_t(id)][i]), std::abs(points[size_t(id)][j])});
  const double unit = std::isfinite(size) && size > 0 ? scale_to_one(size) : 1.0;
  std::vector<std::pair<Vector3d, int>> q;  // (x, y, 0) and the id
  q.reserve(ids.size());
  for (int id : ids)
    q.push_back({Vector3d(flushed(unit * points[size_t(id)][i]), flushed(unit * points[size_t(id)][j]), 0), id});
  std::sort(q.begin(), q.end(), [](const auto& a, const auto& b) {
    return a.first.x() < b.first.x() || (a.first.x() == b.first.x() && a.first.y() < b.first.y());
  });
  q.erase(std::unique(q.begin(), q.end(), [](const auto& a, const auto& b) { return a.first == b.first; }), q.end());
  // b turns left of o -> a where det[a - o; b - o; (0, 0, 1)] > 0: orient3d with o lifted by 1.
  const auto left = [](const Vector3d& o, const Vector3d& a, const Vector3d& b) {
    return orient3d(o, a, b, Vector3d(o.x(), o.y(), 1)) > 0;
  };
  std::vector<std::pair<Vector3d, int>> h;
  for (int pass = 0; pass < 2 && q.size() >= 2; ++pass) {  // lower chain, then upper chain
    const size_t start = h.size();
    for (const auto& p : q) {
      while (h.size() >= start + 2 && !left(h[h.size() - 2].first, h.back().first, p.first)) h.pop_back();
      h.push_back(p);
    }
    h.pop_back();  // each chain's last point starts the other chain
    std::reverse(q.begin(), q.end());
  }
  if (h.empty() && !q.empty()) h.push_back(q.front());
  std::vector<int> corners;
  for (const auto& p : h) corners.push_back(p.second);
  if (normal[k] < 0) std::reverse(corners.begin(), corners.end());
  return corners;
}

namespace {

// The hull of points (scaled to at most 1), exact: the
// quickhull, then its triangles merged into facets.
bool hull_of(const std::vector<Vector3d>& points, HullFacets& out) {
  out.normal.clear(), out.index.clear(), out.start.assign(1, 0);
  Quickhull q(points);
  if (!q.run()) return false;
  // Merge triangles across edges whose far corner lies exactly in their plane (union-find).
  const int n = q.triangles();
  std::vector<int> region(static_cast<size_t>(n));
  for (int f = 0; f < n; ++f) region[size_t(f)] = f;
  const auto root = [&](int x) {
    while (region[size_t(x)] != x) x = region[size_t(x)] = region[size_t(region[size_t(x)])];
    return x;
  };
  for (int f = 0; f < n; ++f) {
    if (!q.alive(f)) continue;
    const auto& t = q.corners(f);
    for (int k = 0; k < 3; ++k) {
      const int g = q.across(f, k);
      if (g < f) continue;  // (each edge once)
      const auto& s = q.corners(g);
      int far = 0;
      while (s[size_t(far)] == t[size_t(k)] || s[size_t(far)] == t[size_t((k + 1) % 3)]) ++far;
      if (q.side(t[0], t[1], t[2], s[size_t(far)]) == 0)
        region[size_t(root(f))] = root(g);
    }
  }
  // A corner touches three regions or more (a point inside a merged facet touches one, a point
  // inside a merged edge two): the distinct (point, region) pairs, counted per point.
  std::vector<std::pair<int, int>> around;
  for (int f = 0; f < n; ++f)
    if (q.alive(f))
      for (int v : q.corners(f)) around.emplace_back(v, root(f));
  std::sort(around.begin(), around.end());
  around.erase(std::unique(around.begin(), around.end()), around.end());
  std::vector<int> regions(points.size(), 0);
  for (const auto& [v, r] : around) ++regions[size_t(v)];
  // Each region's boundary, walked: from a boundary edge (its twin in another region) to the
  // next one around its end within the region; the corners on it form the facet's loop.
  std::vector<char> done(size_t(n) * 3, 0);
  for (int f = 0; f < n; ++f) {
    if (!q.alive(f)) continue;
    for (int k = 0; k < 3; ++k) {
      if (done[size_t(3 * f + k)] || root(q.across(f, k)) == root(f)) continue;
      int g = f, e = k;
      while (!done[size_t(3 * g + e)]) {
        done[size_t(3 * g + e)] = 1;
        const int v = q.corners(g)[size_t(e)];
        if (regions[size_t(v)] >= 3) out.index.push_back(v);
        // The next boundary edge: edge e + 1 of g, or, where its twin is in the region, around
        // the shared corner in the twin.
        int h = g, j = (e + 1) % 3;
        while (root(q.across(h, j)) == root(f)) {
          const int next = q.across(h, j), to = q.corners(h)[size_t(j)];
          int i = 0;
          while (q.corners(next)[size_t(i)] != to) ++i;
          h = next, j = i;  // (the twin's edge from `to`)
        }
        g = h, e = j;
      }
      const std::vector<int> loop(out.index.begin() + out.start.back(), out.index.end());
      // (Never zero for a facet of exact points: a guard, the caller answers with a status.)
      const Vector3d normal = exact_newell(points, loop);
      if (normal == Vector3d::Zero()) return false;
      out.normal.push_back(unit_vector(normal));
      out.start.push_back(int(out.index.size()));
    }
  }
  return out.count() > 0;
}

}  // namespace

bool convex_hull(const std::vector<Vector3d>& input, HullFacets& out) {
  out.normal.clear(), out.index.clear(), out.start.assign(1, 0);
  if (input.size() < 4) return false;
  // Scaled by a power of two to at most 1: exact, and orientations keep their sign.
  double size = 0;
  for (const Vector3d& p : input) size = std::max(size, p.cwiseAbs().maxCoeff());
  if (!std::isfinite(size)) return false;
  const double unit = scale_to_one(size);
  std::vector<Vector3d> points(input.size());
  for (size_t k = 0; k < input.size(); ++k)
    for (int d = 0; d < 3; ++d) points[k][d] = flushed(unit * input[k][d]);
  return hull_of(points, out);
}

bool convex_hull_of_sums(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, HullFacets& out) {
  // The sums as doubles, the points the result's vertices are: the hull of the exact sums has
  // facets that their rounding does not keep planar (a sum of 1e2 and 1e71 rounds to the
  // latter), so that no double plane would hold every rounded sum.
  std::vector<Vector3d> sums(a.size() * b.size());
  for (size_t k = 0; k < sums.size(); ++k) sums[k] = a[k / b.size()] + b[k % b.size()];
  return convex_hull(sums, out);
}

}  // namespace minksum::detail
