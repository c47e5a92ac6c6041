#include "checks.hpp"

#include <algorithm>
#include <map>
#include <random>
#include <set>

namespace minksum::test {

using Eigen::Vector3d;

std::vector<Vector3d> pairwise(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b,
                               double s) {
  std::vector<Vector3d> out;
  for (const auto& p : a)
    for (const auto& q : b) out.push_back(p + s * q);
  return out;
}

namespace {
double max_dot(const std::vector<Vector3d>& pts, const Vector3d& n) {
  double h = -1e300;
  for (const auto& p : pts) h = std::max(h, n.dot(p));
  return h;
}
}  // namespace

testing::AssertionResult valid_sum(const std::vector<Vector3d>& a_pts,
                                   const std::vector<Vector3d>& b_pts, double s,
                                   const ConvexPolytope& A, const ConvexPolytope& B,
                                   const MinkowskiSum& m, double tol, double support_tol,
                                   int directions, unsigned seed) {
  const auto sums = pairwise(a_pts, b_pts, s);
  // Rounding errors scale with the inputs' coordinates, which may dwarf the result (A (-) A).
  double size = 0;
  for (const auto* set : {&a_pts, &b_pts, &sums})
    for (const auto& p : *set) size = std::max(size, p.cwiseAbs().maxCoeff());
  if (m.F != int(m.facets.size()) || m.F != int(m.planes.size()) || m.V != int(m.vertices.size()))
    return testing::AssertionFailure() << "counts do not match the arrays";
  if (!m.euler_ok || m.V - m.E + m.F != 2)
    return testing::AssertionFailure() << "Euler fails: V=" << m.V << " E=" << m.E << " F=" << m.F;
  for (const auto& v : m.vertices) {
    if (!v.point.allFinite()) return testing::AssertionFailure() << "non-finite vertex";
    const Vector3d expect = a_pts[A.input_index[v.i]] + s * b_pts[B.input_index[v.j]];
    if (v.point != expect)
      return testing::AssertionFailure() << "vertex (" << v.i << "," << v.j << ") is not a_i + s b_j";
  }
  for (size_t f = 0; f < m.facets.size(); ++f) {
    const auto& pl = m.planes[f];
    if (!pl.normal.allFinite() || std::abs(pl.normal.norm() - 1) > 1e-12 || !std::isfinite(pl.offset))
      return testing::AssertionFailure() << "facet " << f << " has a bad plane";
    for (const auto& p : sums)
      if (pl.normal.dot(p) > pl.offset + tol * size)
        return testing::AssertionFailure() << "a pairwise sum is outside facet " << f << " by "
                                           << pl.normal.dot(p) - pl.offset;
    Vector3d newell = Vector3d::Zero();
    const auto& loop = m.facets[f];
    for (size_t k = 0; k < loop.size(); ++k) {
      const Vector3d& p = m.vertices[loop[k]].point;
      newell += p.cross(m.vertices[loop[(k + 1) % loop.size()]].point);
      if (std::abs(pl.normal.dot(p) - pl.offset) > tol * size)
        return testing::AssertionFailure() << "vertex off the plane of facet " << f;
    }
    if (newell.dot(pl.normal) <= 0)
      return testing::AssertionFailure() << "facet " << f << " loop is not counter-clockwise";
    const auto& first = m.vertices[loop[0]];
    if (first.i != pl.i || first.j != pl.j)
      return testing::AssertionFailure() << "plane pair is not its loop's first vertex";
  }
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vector3d> verts;
  for (const auto& v : m.vertices) verts.push_back(v.point);
  std::vector<Vector3d> neg_b;
  for (const auto& q : b_pts) neg_b.push_back(s * q);
  for (int k = 0; k < directions; ++k) {
    const Vector3d n = Vector3d(g(rng), g(rng), g(rng)).normalized();
    const double expect = max_dot(a_pts, n) + max_dot(neg_b, n);
    const double got = max_dot(verts, n);
    if (std::abs(got - expect) > support_tol * std::max(size, 1e-300))
      return testing::AssertionFailure() << "support error " << got - expect << " in direction "
                                         << n.transpose();
  }
  return testing::AssertionSuccess();
}

testing::AssertionResult same_sum(const MinkowskiSum& x, const MinkowskiSum& y, double tol) {
  if (x.V != y.V || x.E != y.E || x.F != y.F)
    return testing::AssertionFailure() << "V/E/F " << x.V << "/" << x.E << "/" << x.F << " vs "
                                       << y.V << "/" << y.E << "/" << y.F;
  double size = 0;
  for (const auto& v : x.vertices) size = std::max(size, v.point.cwiseAbs().maxCoeff());
  auto pairs = [](const MinkowskiSum& m, size_t f) {
    std::set<std::pair<int, int>> s;
    for (int k : m.facets[f]) s.insert({m.vertices[k].i, m.vertices[k].j});
    return s;
  };
  // Facets match when they have the same vertex pairs and each one's vertices lie on the other's
  // plane within tol * size. (The normal of a sliver spanned by nearly parallel edges is
  // ill-conditioned; its plane through the vertices is not.)
  auto off_plane = [&](const MinkowskiSum& m, size_t f, const SumPlane& p) {
    double worst = 0;
    for (int k : m.facets[f])
      worst = std::max(worst, std::abs(p.normal.dot(m.vertices[k].point) - p.offset));
    return worst;
  };
  std::map<std::set<std::pair<int, int>>, size_t> by_pairs;
  for (size_t g = 0; g < y.planes.size(); ++g) by_pairs.emplace(pairs(y, g), g);
  for (size_t f = 0; f < x.planes.size(); ++f) {
    auto it = by_pairs.find(pairs(x, f));
    if (it == by_pairs.end()) {
      auto r = testing::AssertionFailure();
      r << "facet " << f << " (n = " << x.planes[f].normal.transpose()
        << ") has no facet with the same vertex pairs:";
      for (const auto& p : pairs(x, f)) r << " (" << p.first << "," << p.second << ")";
      for (size_t g = 0; g < y.planes.size(); ++g)
        if ((y.planes[g].normal - x.planes[f].normal).norm() < 1e-6) {
          r << "; the other has n = " << y.planes[g].normal.transpose() << " with";
          for (const auto& p : pairs(y, g)) r << " (" << p.first << "," << p.second << ")";
        }
      return r;
    }
    const size_t g = it->second;
    const double d = std::max(off_plane(x, f, y.planes[g]), off_plane(y, g, x.planes[f]));
    if (d > tol * std::max(size, 1.0))
      return testing::AssertionFailure() << "facet " << f << " (n = " << x.planes[f].normal.transpose()
                                         << "): the planes differ by " << d << " at its vertices";
  }
  return testing::AssertionSuccess();
}

}  // namespace minksum::test
