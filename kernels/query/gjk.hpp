// GJK on M = A (-) B over two shape views: the support pairs, the features it ends with.
// Templates over the shape views (views.hpp), included by query.cpp alone: one translation
// unit instantiates them, so that the calls between the query's parts stay inline.
#pragma once

#include "geometry/closest.hpp"
#include "query/views.hpp"

namespace minksum {
namespace {

// h_M(n) = max_a n.a - min_b n.b for n and for -n.
template <class A, class B>
void support_pair(const A& a, const B& b, const Vector3d& n, double& plus, double& minus) {
  double amax = -std::numeric_limits<double>::infinity(), amin = -amax, bmax = amax, bmin = amin;
  for (int k = 0; k < a.size(); ++k) {
    const double x = n.dot(a.vertex(k));
    amax = std::max(amax, x), amin = std::min(amin, x);
  }
  for (int k = 0; k < b.size(); ++k) {
    const double x = n.dot(b.vertex(k));
    bmax = std::max(bmax, x), bmin = std::min(bmin, x);
  }
  plus = amax - bmin, minus = bmax - amin;
}

// The support pairs of an answer's features, kept for the next query (three, repeats
// allowed): GJK's nearest simplex, or (depth) the face of M that holds the deepest point.
// And where the answer's normal is a face normal of A (or of B, negated), that face: a sliding
// or resting contact keeps it, and the next query probes it first.
struct Features {
  int a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
  bool valid = false, depth = false;
  int face = -1;
  bool face_of_b = false;
  Vector3d normal = Vector3d::Zero();  // the proof's unit normal, A towards B (0: the search answered)
};

// The nearest features of separated shapes by GJK (Gilbert, Johnson & Keerthi, "A fast
// procedure for computing the distance between complex objects in three-dimensional space",
// IEEE J. Robotics and Automation 4(2), 1988) on M = A (-) B, from the support pairs
// (start_a[k], start_b[k]), k < start (a cold query: one pair; a coherent one: the last
// answer's three): returns 3 with up to three vertices of A (fa) and of B (fb) whose hulls hold
// the nearest points and the weights of its nearest point on them (summing to 1; all 0 where
// it has none), 4 with the four pairs of a tetrahedron of M around the origin, or 0 (NaN).
// Its answer is a guess, rounding and all: certified_distance, certified_depth and
// certified_touching prove it, or the caller does the exhaustive search. M's points are scaled
// by `scale`, a power of two near 1 / the coordinates' magnitude, so that their products
// neither overflow nor underflow. It runs in steps (run), so that a caller can look at its
// direction part way (see face_first).
template <class A, class B>
class Gjk {
 public:
  Gjk(const A& a, const B& b, double scale, const int* start_a, const int* start_b, int start)
      : a_(a), b_(b), scale_(scale) {
    for (int j = 0; j < start; ++j)
      if (!s_.holds(start_a[j], start_b[j])) add(start_a[j], start_b[j]);
  }

  /// Iterates until GJK ends (true) or `limit` iterations in all have passed (false).
  bool run(int limit = kIterations) {
    while (!ended_ && iter_ < std::min(limit, kIterations)) ended_ = step(), ++iter_;
    return ended_ || iter_ == kIterations;
  }

  /// M's nearest point so far (scaled; from B towards A), 0 before the first step.
  const Vector3d& nearest() const { return v_; }

  /// The answer (see above): 3, 4 or 0, with the features and weights.
  int features(int (&fa)[4], int (&fb)[4], double (&weight)[3]) const {
    weight[0] = weight[1] = weight[2] = 0;
    if (result_ != 3) {
      std::copy(s_.ia, s_.ia + 4, fa), std::copy(s_.ib, s_.ib + 4, fb);
      return result_;
    }
    const int n = s_.n;
    for (int j = 0; j < 3; ++j) fa[j] = s_.ia[std::min(j, n - 1)], fb[j] = s_.ib[std::min(j, n - 1)];
    for (int j = 0; j < 3; ++j) weight[j] = j < n && n < 4 ? s_.l[j] : 0.0;
    return 3;
  }

 private:
  static constexpr int kIterations = 64;

  void add(int ka, int kb) { s_.add(ka, kb, scale_ * (a_.vertex(ka) - b_.vertex(kb))); }

  // One iteration; true when GJK ends.
  bool step() {
    // Keep the nearest feature's points only.
    int kept[4];
    const int m = s_.reduce(kept);
    if (m < 0) return result_ = 4, true;   // the origin inside the tetrahedron
    if (m == 0) return result_ = 0, true;  // no weight left (NaN from a degenerate simplex)
    Vector3d v = s_.l[0] * s_.w[0];
    for (int j = 1; j < m; ++j) v += s_.l[j] * s_.w[j];
    if (!(v.squaredNorm() < vv_)) {  // no progress: rounding has the last word; the best one stands
      s_.n = best_n_;
      std::copy(best_a_, best_a_ + 3, s_.ia), std::copy(best_b_, best_b_ + 3, s_.ib), std::copy(best_l_, best_l_ + 3, s_.l);
      return true;
    }
    vv_ = v.squaredNorm(), v_ = v;
    best_n_ = s_.n;
    std::copy(s_.ia, s_.ia + 3, best_a_), std::copy(s_.ib, s_.ib + 3, best_b_), std::copy(s_.l, s_.l + 3, best_l_);
    // M's support point in -v: A's lowest vertex along v minus B's highest.
    double lo, hi;
    const int ka = highest(a_, -v, lo), kb = highest(b_, v, hi);
    lo = -lo;
    // Stop when M reaches no further towards the origin than v does (to rounding), or repeats.
    if (!(vv_ - scale_ * (lo - hi) > 1e-13 * vv_)) return true;
    if (s_.holds(ka, kb) || s_.n == 4) return true;
    add(ka, kb);
    return false;
  }

  const A& a_;
  const B& b_;
  double scale_;
  detail::PairSimplex s_;
  Vector3d v_ = Vector3d::Zero();
  double vv_ = std::numeric_limits<double>::infinity();
  int best_a_[3] = {}, best_b_[3] = {}, best_n_ = 0;  // the nearest simplex so far (ties can stall)
  double best_l_[3] = {};
  int iter_ = 0, result_ = 3;
  bool ended_ = false;
};

// GJK from the start to its end (see Gjk).
template <class A, class B>
int gjk_features(const A& a, const B& b, double scale, const int* start_a, const int* start_b, int start, int (&fa)[4],
                 int (&fb)[4], double (&weight)[3]) {
  Gjk<A, B> gjk(a, b, scale, start_a, start_b, start);
  gjk.run();
  return gjk.features(fa, fb, weight);
}

}  // namespace
}  // namespace minksum
