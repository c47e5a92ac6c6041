// The reference path: the object-space method exactly as the paper describes it
// (Section 2.2, equations (5)-(9)), in plain scalar double code. Everything else is tested
// against it, so it favours readability over speed: O(|A||B| (F_A + F_B + E_A E_B)).
//
// About the "u V_A" term of the paper's equations (2) and (5): it adds A's own vertices to the
// candidate set, which is only harmless when B contains the origin (then a_i = a_i + 0 lies in
// the hull anyway) and wrong otherwise (a_i need not belong to A (+) B at all). We therefore use
// V = {a_i + b_j} alone, which is the definition (1) of the sum.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "core/hull.hpp"
#include "core/scale.hpp"
#include "sum/sum_internal.hpp"

namespace minksum::detail {

using Eigen::Vector3d;

namespace {

// Relative tolerance, in units of the sum's extent: a vertex within kPushTol of the pushed
// plane is extreme (its corners are then those of the extremes' planar hull).
constexpr double kPushTol = 1e-9;

// Edge directions of a polytope, one per edge.
std::vector<Vector3d> edge_directions(const ConvexPolytope& p) {
  std::vector<Vector3d> d;
  for (const auto& e : p.edges) d.push_back(p.vertices[e.v1] - p.vertices[e.v0]);
  return d;
}

}  // namespace

void sum_reference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out) {
  const int nb = int(b.vertices.size());
  // Step 1: the vertex set V = {a_i + b_j}, vertex k = i * |B| + j (the paper's index tracking).
  std::vector<Vector3d> V;
  for (const auto& va : a.vertices)
    for (const auto& vb : b.vertices) V.push_back(va + vb);
  double scale = 0;
  for (const auto& p : V) scale = std::max(scale, p.cwiseAbs().maxCoeff());
  Vector3d lo = V[0], hi = V[0];
  for (const auto& p : V) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double extent = (hi - lo).norm();
  const double push_tol = kPushTol * std::max(extent, 1e-300) + 4e-16 * scale;

  // Step 2: candidate normals N_A u N_B u {+-(e_A x e_B)}, equation (7).
  std::vector<Vector3d> normals;
  for (const auto& f : a.faces) normals.push_back(f.normal);
  for (const auto& f : b.faces) normals.push_back(f.normal);
  const auto ea = edge_directions(a), eb = edge_directions(b);
  for (const auto& da : ea)
    for (const auto& db : eb) {
      // (Unit edges first: a cross product of edges at 1e100 would overflow its norm.)
      const Vector3d c = unit_vector(da).cross(unit_vector(db));
      // Parallel edges sweep no facet; their cross product is noise, not a direction.
      if (c.norm() <= 1e-12) continue;
      normals.push_back(c.normalized());
      normals.push_back(-c.normalized());
    }

  // Step 3: push every plane to its extreme vertices, equations (4) and (9); keep it when they
  // hold three non-collinear points; merge candidates that find the same facet.
  // n . v_k for v_k = a_i + b_j is evaluated as n . a_i + n . b_j: the same numbers as the
  // paper's loop over V, but the extreme pairs can then only come from near-extreme a_i and b_j,
  // which keeps the test suite's thousands of random pairs affordable.
  std::map<std::vector<int>, std::pair<size_t, double>> seen;  // corners -> facet, spread
  std::vector<FacetLoop> facets;
  // Each candidate's heights over A and B, from the coordinates as three arrays: a loop that
  // vectorises in Release and stays cheap at the sanitizer build's -O1, where Eigen's product
  // expressions are not inlined (they took 70 % of its tests).
  struct Columns {
    std::vector<double> x, y, z, h;
    explicit Columns(const std::vector<Vector3d>& p) {
      for (const auto& v : p) x.push_back(v[0]), y.push_back(v[1]), z.push_back(v[2]);
      h.resize(p.size());
    }
    double heights(const Vector3d& n) {  // (returns the largest)
      const double nx = n[0], ny = n[1], nz = n[2];
      for (size_t i = 0; i < h.size(); ++i) h[i] = nx * x[i] + ny * y[i] + nz * z[i];
      return Eigen::Map<const Eigen::ArrayXd>(h.data(), Eigen::Index(h.size())).maxCoeff();
    }
  } ca(a.vertices), cb(b.vertices);
  const std::vector<double> &da = ca.h, &db = cb.h;
  std::vector<int> extreme;  // (reused: most of the E_A E_B candidates find two pairs or fewer)
  for (const auto& n : normals) {
    const double ha = ca.heights(n), hb = cb.heights(n);
    extreme.clear();
    for (int i = 0; i < int(da.size()); ++i) {
      if (da[i] < ha - push_tol) continue;
      for (int j = 0; j < nb; ++j)
        if (da[i] + db[j] >= ha + hb - push_tol) extreme.push_back(i * nb + j);
    }
    if (extreme.size() < 3) continue;
    std::vector<int> corners = planar_hull(V, extreme, n);
    if (corners.size() < 3) continue;
    // Several candidates can find the same facet; keep the plane that fits its corners best.
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (int k : corners) lo = std::min(lo, n.dot(V[k])), hi = std::max(hi, n.dot(V[k]));
    std::vector<int> key = corners;
    std::sort(key.begin(), key.end());
    auto [it, fresh] = seen.emplace(key, std::make_pair(facets.size(), hi - lo));
    if (!fresh) {
      if (hi - lo < it->second.second) facets[it->second.first].normal = n, it->second.second = hi - lo;
      continue;
    }
    FacetLoop f{n, {}};
    for (int k : corners) f.loop.emplace_back(k / nb, k % nb);
    facets.push_back(std::move(f));
  }
  assemble(a.vertices, b.vertices, facets, out);
}

}  // namespace minksum::detail
