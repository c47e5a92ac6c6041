// Contact patches in the plane across a contact normal (see patch.hpp).
#include "query/patch.hpp"

#include "simd/separating_axes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

// `in` clipped to the half-plane left of the directed line a -> b (within tol), into x.
void clip(const Patch& in, const Eigen::Vector2d& a, const Eigen::Vector2d& b, double tol, Patch& x) {
  x.size = 0;
  if (in.size == 0) return;
  const Eigen::Vector2d e = b - a;
  const double scale = tol * e.norm();
  double h[kPatch];  // each point's height over the line, once
  for (int k = 0; k < in.size; ++k) h[k] = cross2(e, in.p[k] - a);
  for (int k = 0; k < in.size; ++k) {
    const int next = after(in, k);
    const bool keep = h[k] >= -scale;
    if (keep && x.size < kPatch) x.p[x.size++] = in.p[k];
    if (keep != (h[next] >= -scale) && x.size < kPatch)
      x.p[x.size++] = in.p[k] + (h[k] / (h[k] - h[next])) * (in.p[next] - in.p[k]);
  }
}

// x's points into y (not the whole buffer: a patch holds 2 KiB).
void assign(Patch& y, const Patch& x) {
  y.size = x.size;
  std::copy(x.p, x.p + x.size, y.p);
}

// Whether the convex polygon x has a corner under 30 degrees (its edges' turn there over 150).
bool sharp_corner(const Patch& x) {
  for (int k = 0; k < x.size; ++k) {
    const Eigen::Vector2d in = x.p[k] - x.p[(k + x.size - 1) % x.size], out = x.p[after(x, k)] - x.p[k];
    const double d = in.dot(out);
    if (d < 0 && d * d > 0.75 * in.squaredNorm() * out.squaredNorm()) return true;
  }
  return false;
}

// Whether c lies in the convex polygon x (counter-clockwise, 3 or more vertices; within tol).
// Within tol of every edge's line is not enough where two edges meet at a tiny angle: the
// wedge beyond that corner lies within tol of both lines as far as tol / sin(angle / 2) (a
// sliver's face at 1e86 held a point 2.9e76 beyond its corner, and two shapes that far apart
// touched). Outside a line, c must lie within 4 tol of an edge (4: a right angle's corner
// region reaches sqrt(2) tol, as it did). Within tol of a line c's side of it is rounding (the
// same sliver, turned, put a point 2.9e76 beyond that corner inside both its edges' lines by
// their rounding), so c is inside only where it is more than tol inside every line.
bool holds(const Patch& x, const Eigen::Vector2d& c, double tol) {
  bool inside = true;
  for (int k = 0; k < x.size; ++k) {
    const Eigen::Vector2d e = x.p[after(x, k)] - x.p[k];
    const double h = cross2(e, c - x.p[k]);
    if (h < -tol * e.norm()) return false;
    inside = inside && h > tol * e.norm();
  }
  if (inside) return true;
  double near2 = std::numeric_limits<double>::infinity();
  for (int k = 0; k < x.size; ++k) {
    const Eigen::Vector2d &p = x.p[k], e = x.p[after(x, k)] - p;
    const double len2 = e.squaredNorm();
    const Eigen::Vector2d y = p + (len2 > 0 ? std::clamp((c - p).dot(e) / len2, 0.0, 1.0) : 0.0) * e;
    near2 = std::min(near2, (y - c).squaredNorm());
  }
  return near2 <= 16 * tol * tol;
}

// The point of the set x (a point, a segment or a convex polygon) nearest c.
Eigen::Vector2d nearest_in(const Patch& x, const Eigen::Vector2d& c, double tol) {
  // (A clipped segment has three or more points on a line: no inside.)
  double extent = 0;
  for (int k = 1; k < x.size; ++k) extent = std::max(extent, (x.p[k] - x.p[0]).norm());
  if (x.size >= 3 && area2(x) > tol * extent && holds(x, c, tol)) return c;
  Eigen::Vector2d best = x.p[0];
  for (int k = 0; k < x.size; ++k) {
    const Eigen::Vector2d &p = x.p[k], e = x.p[after(x, k)] - p;
    const double len2 = e.squaredNorm();
    const Eigen::Vector2d y = p + (len2 > 0 ? std::clamp((c - p).dot(e) / len2, 0.0, 1.0) : 0.0) * e;
    if ((y - c).squaredNorm() < (best - c).squaredNorm()) best = y;
  }
  return best;
}

}  // namespace

double area2(const Patch& x) {
  double s = 0;
  for (int k = 0; k < x.size; ++k) s += cross2(x.p[k], x.p[after(x, k)]);
  return s;
}

// A patch narrower than tol made what it is at that tolerance: a segment between its two
// farthest points, or a point. (At coordinates of 1e86 a face 50 wide rounds to a polygon of
// coincident points, whose zero-length edges would hold every point.)
void settle(Patch& x, double tol) {
  if (x.size < 2) return;
  if (x.size >= 3) {  // a polygon kept as it is, without the two sweeps: one pass for its box
    // (The sweeps' extent is at least |p1 - p0| and at most the box's diagonal.)
    Eigen::Vector2d lo = x.p[0], hi = lo;
    for (int k = 1; k < x.size; ++k) lo = lo.cwiseMin(x.p[k]), hi = hi.cwiseMax(x.p[k]);
    if ((x.p[1] - x.p[0]).norm() > tol && std::abs(area2(x)) > tol * (hi - lo).norm()) return;
  }
  const auto farthest = [&](const Eigen::Vector2d& from) {
    int best = 0;
    for (int k = 1; k < x.size; ++k)
      if ((x.p[k] - from).squaredNorm() > (x.p[best] - from).squaredNorm()) best = k;
    return best;
  };
  const int i = farthest(x.p[0]), j = farthest(x.p[i]);
  const double extent = (x.p[j] - x.p[i]).norm();
  if (!(extent > tol)) {
    x.size = 1;
  } else if (x.size >= 3 && !(std::abs(area2(x)) > tol * extent)) {
    const Eigen::Vector2d a = x.p[i], b = x.p[j];
    x.p[0] = a, x.p[1] = b, x.size = 2;
  }
}

// Whether the point x lies in the set y (a point, a segment or a convex polygon; within tol).
bool meets(const Eigen::Vector2d& x, const Patch& y, double tol) {
  if (y.size >= 3) return holds(y, x, tol);
  return (nearest_in(y, x, tol) - x).norm() <= tol;
}

// The overlap of the sets small and large (points, segments or convex polygons of 2 or more
// points each; within tol), into `overlap`: empty where they do not meet. Segments across
// each other meet at a point (an edge across an edge: a penetration along their cross product
// ends with them crossing).
void overlap_of(const Patch& small, const Patch& large, double tol, Patch& overlap) {
  Patch spare;  // clipped back and forth between it and `overlap`
  if (large.size >= 3) {
    const Patch* from = &small;
    for (int k = 0; k < large.size && from->size > 0; ++k) {
      Patch& to = from == &overlap ? spare : overlap;
      clip(*from, large.p[k], large.p[after(large, k)], tol, to);
      from = &to;
    }
    if (from != &overlap) assign(overlap, *from);
    // (Clipped by the lines within tol, a point may lie in the wedge beyond a sharp corner of
    // `large` (under 30 degrees: beyond 4 tol), far from it: there only the points that lie
    // within tol of it (holds) are the overlap.)
    if (!sharp_corner(large)) return;
    int kept = 0;
    for (int k = 0; k < overlap.size; ++k)
      if (holds(large, overlap.p[k], tol)) overlap.p[kept++] = overlap.p[k];
    overlap.size = kept;
    return;
  }
  // Two segments: on one line (clipped to each other), or across at a point.
  const Eigen::Vector2d e = large.p[1] - large.p[0], f = small.p[1] - small.p[0];
  const double len = e.norm();
  bool collinear = true;
  for (int k = 0; k < 2; ++k) collinear = collinear && std::abs(cross2(e, small.p[k] - large.p[0])) <= tol * len;
  if (!collinear) {
    // (small.p[0] + s f lies on large's line at s = e x (large.p[0] - small.p[0]) / e x f.)
    const double across = cross2(e, f);
    overlap.size = 0;
    if (!(across != 0)) return;  // parallel lines apart
    const Eigen::Vector2d x = small.p[0] + std::clamp(cross2(e, large.p[0] - small.p[0]) / across, 0.0, 1.0) * f;
    if (meets(x, large, tol)) overlap.p[0] = x, overlap.size = 1;
    return;
  }
  const Eigen::Vector2d across(-e.y(), e.x());
  clip(small, large.p[0] + across, large.p[0], tol, spare);    // beyond large.p[0]
  clip(spare, large.p[1], large.p[1] + across, tol, overlap);  // before large.p[1]
}

void overlap_of_sets(const Patch& P, const Patch& Q, double tol, Patch& overlap) {
  if (P.size == 1 || Q.size == 1) {
    const Patch& point = P.size == 1 ? P : Q;
    overlap.size = 0;
    if (meets(point.p[0], P.size == 1 ? Q : P, tol)) assign(overlap, point);
  } else if (Q.size >= 3) {
    overlap_of(P, Q, tol, overlap);  // A's set clipped by B's: counter-clockwise as A's was
  } else {
    overlap_of(Q, P, tol, overlap);  // a segment of B's across A's set
  }
}

void tidy(Patch& x, double tol) {
  const double tol2 = tol * tol;
  int kept = 0;
  for (int k = 0; k < x.size; ++k)
    if (kept == 0 || (x.p[k] - x.p[kept - 1]).squaredNorm() > tol2) x.p[kept++] = x.p[k];
  while (kept > 1 && (x.p[kept - 1] - x.p[0]).squaredNorm() <= tol2) --kept;
  x.size = kept;
  settle(x, tol);
}

// The witness on A's and B's level sets P and Q (see Patch); false where they do not meet.
bool patch_point(const Patch& P, const Patch& Q, double tol, Eigen::Vector2d& x) {
  if (P.size == 1 || Q.size == 1) {
    const bool p_point = P.size == 1;
    x = (p_point ? P : Q).p[0];
    return meets(x, p_point ? Q : P, tol);
  }
  const bool p_smaller = std::abs(area2(P)) <= std::abs(area2(Q));
  const Patch &small = p_smaller ? P : Q, &large = p_smaller ? Q : P;
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (int k = 0; k < small.size; ++k) c += small.p[k];
  c /= small.size;
  if (large.size >= 3 && holds(large, c, tol)) return x = c, true;
  Patch overlap;
  overlap_of(small, large, tol, overlap);
  if (overlap.size == 0) return false;
  x = overlap.size == 1 ? overlap.p[0] : nearest_in(overlap, c, tol);
  return true;
}

void level_patch(const Box& x, const BoxLevel& L, double tau, const Vector3d& u, const Vector3d& w, Patch& P,
                 ContactPatch::Feature* feature) {
  const auto put = [&](const Vector3d& p) { P.p[P.size++] = Eigen::Vector2d(u.dot(p), w.dot(p)); };
  const auto edge = [&](int j) { return Vector3d(x.half_extents[L.free[j]] * x.rotation.col(L.free[j])); };
  using Kind = ContactPatch::Feature::Kind;
  const Vector3d& base = L.base;
  const int code = L.code;
  P.size = 0;
  if (L.nfree == 0) {
    put(base);
    if (feature) *feature = {Kind::Vertex, {code, -1}};
  } else if (L.nfree == 1) {
    put(base - edge(0)), put(base + edge(0));
    if (feature) *feature = {Kind::Edge, {code, code | 1 << L.free[0]}};
  } else {
    put(base - edge(0) - edge(1)), put(base + edge(0) - edge(1)), put(base + edge(0) + edge(1)),
        put(base - edge(0) + edge(1));
    if (area2(P) < 0) std::reverse(P.p, P.p + 4);
    const int fixed = 3 - L.free[0] - L.free[1];  // polytope_from_box's face 2 a + (its + side)
    if (feature) *feature = {Kind::Face, {2 * fixed + (code >> fixed & 1), -1}};
  }
  // (Narrower than tau only where a free edge is: at coordinates of 1e86, or a speck of a box.)
  if (L.nfree > 0 && std::min(x.half_extents[L.free[0]], x.half_extents[L.free[L.nfree - 1]]) * 2 <= tau)
    settle(P, tau);
}

bool box_level(const Box& x, const Vector3d& m, double sign, double tau, const Vector3d& u, const Vector3d& w, Patch& P,
               double& height, ContactPatch::Feature* feature) {
  BoxLevel L;
  if (!box_level_of(x, m, sign, tau, L)) return false;
  height = m.dot(L.base);
  level_patch(x, L, tau, u, w, P, feature);
  return true;
}

// The separating axis test on the 15 axes of a box pair (Gottschalk, Lin and Manocha, "OBBTree",
// 1996): A (-) B is a zonotope whose facet normals are the boxes' axes and the cross products of
// an axis of A with one of B. So the largest separation s over the 15 axes is minus the
// penetration depth when s <= 0 (the origin's nearest facet), and a lower bound of the
// distance when s > 0, equal to it exactly where the two supporting sets along that axis
// overlap seen along it (then a point of A and one of B lie s apart along it). Axes within 1e-12
// of parallel give no facet; those within 1e-6 give a normal too rounded to decide on: the
// general path answers, as it does where the sets along the best axis miss.
BoxPatch box_pair_patch(const Box& a, const Box& b, double margin, ContactPatch& out) {
  const double reach = std::max(a.center.cwiseAbs().maxCoeff() + a.half_extents.sum(),
                                b.center.cwiseAbs().maxCoeff() + b.half_extents.sum());
  if (!(reach > 1e-60 && reach < 1e60)) return BoxPatch::Undecided;  // (products that under- or overflow)
  const double tau = 256 * std::numeric_limits<double>::epsilon() * reach;
  // The 15 axes as the box pair query visits them (SeparatingAxes), in A's frame.
  struct Plain {  // one double: SeparatingAxes' value operations
    using B = double;
    static double abs(double x) { return std::abs(x); }
    static double fma(double x, double y, double z) { return x * y + z; }  // (no libm call)
  };
  struct PatchArch {};
  double C[3][3], cA[3], cB[3];
  const Vector3d c = a.center - b.center;
  for (int i = 0; i < 3; ++i) {
    cA[i] = a.rotation.col(i).dot(c), cB[i] = b.rotation.col(i).dot(c);
    for (int j = 0; j < 3; ++j) C[i][j] = a.rotation.col(i).dot(b.rotation.col(j));
  }
  double best = -std::numeric_limits<double>::infinity();
  int axis = 0;
  bool undecided = false;
  SeparatingAxes<Plain, PatchArch>::visit(
      C, cA, cB, a.half_extents.data(), b.half_extents.data(),
      [&](int p, double d) {
        if (d > best) best = d, axis = p;
      },
      [&](int p, double d, double len2) {
        // Parallel axes (1e-12) give no facet; nearly parallel ones (1e-6), a normal too
        // rounded to decide on. (A division only for an axis that wins.)
        if (len2 < 1e-24) return;
        undecided = undecided || len2 < 1e-12;
        const double len = std::sqrt(len2);
        if (d > best * len) best = d / len, axis = p;
      });
  if (undecided) return BoxPatch::Undecided;
  if (best > margin) return BoxPatch::Apart;
  // (A face axis is a column of a rotation accepted as orthonormal to 1e-9, posed: unit to
  // about that. The patch's normal is unit to rounding, as its users read it.)
  Vector3d m = axis < 3   ? Vector3d(a.rotation.col(axis)).normalized()
               : axis < 6 ? Vector3d(b.rotation.col(axis - 3)).normalized()
                          : a.rotation.col((axis - 6) / 3).cross(b.rotation.col((axis - 6) % 3)).normalized();
  if (m.dot(c) > 0) m = -m;  // from A towards B
  const Vector3d u = m.unitOrthogonal(), w = m.cross(u);
  Patch P, Q, O;
  double top, bottom;
  ContactPatch::Feature fa, fb;
  if (!box_level(a, m, 1.0, tau, u, w, P, top, &fa) || !box_level(b, m, -1.0, tau, u, w, Q, bottom, &fb))
    return BoxPatch::Undecided;
  overlap_of_sets(P, Q, tau, O);
  if (O.size == 0) return BoxPatch::Undecided;  // the distance is not this axis's: an edge or a vertex of A (-) B
  tidy(O, tau);
  // The depth is the axis test's own (-best, the same number that decided the verdict): the
  // levels' top - bottom may round to the other side of 0 on a touching pair.
  out.normal = m, out.depth = -best, out.size = O.size;
  out.feature_a = fa, out.feature_b = fb;
  for (int k = 0; k < O.size; ++k) out.points[k] = O.p[k].x() * u + O.p[k].y() * w + top * m;
  return BoxPatch::Done;
}

// The same for a box and a triangle (flat: its one face seen from either side), on their 13
// axes: the box's 3, the triangle's normal and the 9 crosses of a box axis with an edge.
BoxPatch box_triangle_patch(const Box& a, const Triangle& t, double margin, ContactPatch& out) {
  const Vector3d v[3] = {t.a, t.b, t.c};
  double reach = a.center.cwiseAbs().maxCoeff() + a.half_extents.sum();
  for (const Vector3d& x : v) reach = std::max(reach, x.cwiseAbs().maxCoeff());
  if (!(reach > 1e-60 && reach < 1e60)) return BoxPatch::Undecided;
  const double tau = 256 * std::numeric_limits<double>::epsilon() * reach;
  // Unit edges first (products of raw coordinates overflow); a sliver's normal is rounding.
  const Vector3d e[3] = {(v[1] - v[0]).normalized(), (v[2] - v[1]).normalized(), (v[0] - v[2]).normalized()};
  const Vector3d normal = e[0].cross(e[1]);
  if (!(normal.norm() >= 1e-6)) return BoxPatch::Undecided;
  double best = -std::numeric_limits<double>::infinity();
  Vector3d m = Vector3d::UnitZ();
  const auto consider = [&](const Vector3d& axis) {  // (unit) either way: B above A, or below
    double r = 0, lo = axis.dot(v[0]), hi = lo;
    for (int k = 0; k < 3; ++k) r += a.half_extents[k] * std::abs(axis.dot(a.rotation.col(k)));
    for (int k = 1; k < 3; ++k) lo = std::min(lo, axis.dot(v[k])), hi = std::max(hi, axis.dot(v[k]));
    const double c = axis.dot(a.center), above = lo - (c + r), below = (c - r) - hi;
    if (std::max(above, below) > best) best = std::max(above, below), m = above >= below ? axis : Vector3d(-axis);
  };
  for (int k = 0; k < 3; ++k) consider(a.rotation.col(k).normalized());  // (as in box_pair_patch)
  consider(normal.normalized());
  for (int i = 0; i < 3; ++i)
    for (const Vector3d& edge : e) {
      const Vector3d axis = a.rotation.col(i).cross(edge);
      const double len = axis.norm();
      if (len < 1e-12) continue;
      if (len < 1e-6) return BoxPatch::Undecided;
      consider(axis / len);
    }
  if (best > margin) return BoxPatch::Apart;
  const Vector3d u = m.unitOrthogonal(), w = m.cross(u);
  Patch P, Q, O;
  double top;
  ContactPatch::Feature fa, fb;
  if (!box_level(a, m, 1.0, tau, u, w, P, top, &fa)) return BoxPatch::Undecided;
  // The triangle's lowest set along m: a corner, an edge or the triangle, counter-clockwise.
  const double h[3] = {m.dot(v[0]), m.dot(v[1]), m.dot(v[2])}, bottom = std::min({h[0], h[1], h[2]});
  using Kind = ContactPatch::Feature::Kind;
  Q.size = 0;
  for (int k = 0; k < 3; ++k)
    if (h[k] - bottom <= tau) {
      if (Q.size < 2) fb.index[Q.size] = k;  // (all three: the face, below)
      Q.p[Q.size++] = Eigen::Vector2d(u.dot(v[k]), w.dot(v[k]));
    }
  if (Q.size == 3 && area2(Q) < 0) std::reverse(Q.p, Q.p + 3);
  fb.kind = Q.size == 3 ? Kind::Face : Q.size == 2 ? Kind::Edge : Kind::Vertex;
  if (Q.size == 3) fb.index[0] = 0, fb.index[1] = -1;
  settle(Q, tau);
  overlap_of_sets(P, Q, tau, O);
  if (O.size == 0) return BoxPatch::Undecided;
  tidy(O, tau);
  // The depth is the axis test's own (-best, the same number that decided the verdict): the
  // levels' top - bottom may round to the other side of 0 on a touching pair.
  out.normal = m, out.depth = -best, out.size = O.size;
  out.feature_a = fa, out.feature_b = fb;
  for (int k = 0; k < O.size; ++k) out.points[k] = O.p[k].x() * u + O.p[k].y() * w + top * m;
  return BoxPatch::Done;
}

}  // namespace minksum::detail

namespace minksum {

// The largest quadrilateral in a convex polygon: for each first corner i and opposite corner k,
// the best j between them and l after k, each found by advancing from the best for the
// previous k (the area of (i, j, k) is unimodal along the chain from i to k, and its best j
// moves forward with k: the rotating calipers' argument, Shamos 1978). O(n^2) for n points.
void reduce_contact_patch(ContactPatch& patch) {
  const int n = patch.size;
  if (n <= 4) return;
  const Eigen::Vector3d* p = patch.points;
  const Eigen::Vector3d normal = patch.normal;
  // (Indices unwrapped: i <= j < k < l < i + n.)
  const auto area = [&](int i, int j, int k) {
    const Eigen::Vector3d &a = p[i % n], &b = p[j % n], &c = p[k % n];
    return (b - a).cross(c - a).dot(normal);
  };
  double best = -1;
  int corner[4] = {0, 1, 2, 3};
  for (int i = 0; i < n; ++i)
    for (int k = i + 2, j = i + 1, l = i + 3; k <= i + n - 2; ++k) {
      while (j + 1 < k && area(i, j + 1, k) >= area(i, j, k)) ++j;
      l = std::max(l, k + 1);
      while (l + 1 < i + n && area(i, k, l + 1) >= area(i, k, l)) ++l;
      if (const double a = area(i, j, k) + area(i, k, l); a > best)
        best = a, corner[0] = i, corner[1] = j % n, corner[2] = k % n, corner[3] = l % n;
    }
  const Eigen::Vector3d q[4] = {p[corner[0]], p[corner[1]], p[corner[2]], p[corner[3]]};
  std::copy(q, q + 4, patch.points);
  patch.size = 4;
}

}  // namespace minksum
