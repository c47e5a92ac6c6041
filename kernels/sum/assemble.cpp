// A sum's result from its facets' support loops, its closed-manifold check, and the paper's
// Section 3 corrector that rebuilds it from the hull of the pairwise sums.
#include "sum/sum_internal.hpp"
#include "sum/pair_numbering.hpp"

#include "core/hull.hpp"
#include "core/manifold.hpp"
#include "core/scale.hpp"

#include <algorithm>
#include <limits>

namespace minksum {

using Eigen::Vector3d;

namespace detail {

bool closed_manifold(const MinkowskiSum& m) {
  thread_local std::vector<int> scratch;
  return m.F >= 0 && m.loop_start.size() == size_t(m.F) + 1 &&
         pair_edges(m.loop_start.data(), m.F, m.loop_vertex.data(), int(m.vertices.size()), nullptr, scratch);
}

void assemble(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, std::vector<FacetLoop>& facets,
              MinkowskiSum& out) {
  // The output's vectors keep their capacity (a caller that reuses `out` allocates once), and
  // the scratch tables are per thread: a sum allocates only while it grows.
  out.planes.clear(), out.vertices.clear(), out.loop_vertex.clear();
  out.loop_start.assign(1, 0);
  out.V = out.E = out.F = 0;
  out.euler_ok = out.corrected = false;
  thread_local PairNumbering pairs;
  size_t kept = 0, entries = 0;
  for (auto& f : facets) {
    // Consecutive repeats come from zero-length arcs of flat operands; drop them, then drop
    // facets that collapse to fewer than three pairs (they have zero area).
    auto& l = f.loop;
    l.erase(std::unique(l.begin(), l.end()), l.end());
    while (l.size() > 1 && l.front() == l.back()) l.pop_back();
    if (l.size() < 3) continue;
    // Start each loop at its smallest pair so that the plane's pair does not depend on the path.
    std::rotate(l.begin(), std::min_element(l.begin(), l.end()), l.end());
    entries += l.size();
    if (&facets[kept] != &f) facets[kept] = std::move(f);
    ++kept;
  }
  facets.resize(kept);
  // The loops as pair codes, then as vertex indices once every pair is known.
  pairs.reset(int(a.size()), int(b.size()), entries);
  out.loop_vertex.reserve(entries), out.loop_start.reserve(facets.size() + 1), out.planes.reserve(facets.size());
  for (const auto& f : facets) {
    for (const auto& p : f.loop) out.loop_vertex.push_back(pairs.code(p.first, p.second));
    out.loop_start.push_back(int(out.loop_vertex.size()));
  }
  pairs.finish(out.loop_vertex.data(), out.loop_vertex.size(), [&](int, int i, int j) {
    out.vertices.push_back(SumVertex{i, j, a[size_t(i)] + b[size_t(j)]});
  });
  for (size_t f = 0; f < facets.size(); ++f) {
    const auto& first = facets[f].loop[0];
    SumPlane plane{unit_vector(facets[f].normal), -std::numeric_limits<double>::infinity(), first.first, first.second};
    // The offset is the largest over the facet's vertices, so no vertex is ever cut off.
    for (int k = out.loop_start[f]; k < out.loop_start[f + 1]; ++k)
      plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[size_t(out.loop_vertex[size_t(k)])].point));
    out.planes.push_back(plane);
  }
  out.V = int(out.vertices.size());
  out.E = int(out.loop_vertex.size() / 2);
  out.F = int(facets.size());
  out.euler_ok = out.F >= 4 && out.V - out.E + out.F == 2 && closed_manifold(out);
}

Status hull_corrector(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, MinkowskiSum& out) {
  const int nb = int(b.size());
  HullFacets hull;
  if (!convex_hull_of_sums(a, b, hull)) {  // (an empty result, its buffers kept for the next call)
    out.planes.clear(), out.loop_start.clear(), out.loop_vertex.clear(), out.vertices.clear();
    out.V = out.E = out.F = 0, out.euler_ok = false, out.radius = 0;
    return Status::HullFailed;
  }
  std::vector<FacetLoop> facets;
  for (int h = 0; h < hull.count(); ++h) {
    FacetLoop f{hull.normal[size_t(h)], {}};
    for (int k = hull.start[size_t(h)]; k < hull.start[size_t(h) + 1]; ++k)
      f.loop.emplace_back(hull.index[size_t(k)] / nb, hull.index[size_t(k)] % nb);
    facets.push_back(std::move(f));
  }
  assemble(a, b, facets, out);
  out.corrected = true;
  // (The exact hull always closes; the check guards the assembly all the same: a clear error
  // rather than an inconsistent "Ok".)
  return out.euler_ok ? Status::Ok : Status::HullFailed;
}

}  // namespace detail

}  // namespace minksum
