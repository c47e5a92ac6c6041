// A sum's result from its facets' support loops, its closed-manifold check, and the paper's
// Section 3 corrector that rebuilds it from the hull of the pairwise sums.
#include "sum/sum_internal.hpp"

#include "core/hull.hpp"

#include <algorithm>

namespace minksum {

using Eigen::Vector3d;

namespace detail {

bool closed_manifold(const MinkowskiSum& m) {
  // Every directed edge u -> v once, and v -> u once. Outgoing edges are grouped per vertex (a
  // few per vertex), so each check is a short scan.
  thread_local std::vector<int> start, head, fill;
  const size_t V = m.vertices.size();
  start.assign(V + 1, 0);
  head.resize(m.loop_vertex.size());
  for (int u : m.loop_vertex) ++start[size_t(u) + 1];
  for (size_t v = 0; v < V; ++v) start[v + 1] += start[v];
  fill.assign(start.begin(), start.end() - 1);
  for (int f = 0; f < m.F; ++f) {
    const Loop loop = m.facet(f);
    for (int k = 0; k < loop.size(); ++k) head[size_t(fill[loop[k]]++)] = loop[(k + 1) % loop.size()];
  }
  const auto count = [&](int u, int v) {
    int n = 0;
    for (int k = start[u]; k < start[u + 1]; ++k) n += head[k] == v;
    return n;
  };
  for (size_t u = 0; u < V; ++u)
    for (int k = start[u]; k < start[u + 1]; ++k)
      if (count(int(u), head[k]) != 1 || count(head[k], int(u)) != 1) return false;
  return true;
}

void assemble(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, std::vector<FacetLoop>& facets,
              MinkowskiSum& out) {
  // The output's vectors keep their capacity (a caller that reuses `out` allocates once), and
  // the scratch tables are per thread: a sum allocates only while it grows.
  out.planes.clear(), out.vertices.clear(), out.loop_vertex.clear();
  out.loop_start.assign(1, 0);
  out.V = out.E = out.F = 0;
  out.euler_ok = out.corrected = false;
  thread_local std::vector<int> start, fill, number;
  thread_local std::vector<long long> slots, distinct;
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
  // Vertices are the distinct pairs (i, j), numbered in (i, j) order, found through a hash
  // table of codes i |B| + j (linear probing) and ordered by a counting sort on i.
  const long long nb = (long long)(b.size());
  size_t cap = 16;
  while (cap < 2 * entries) cap *= 2;
  slots.assign(cap, -1), number.resize(cap), distinct.clear();
  const auto slot = [&](long long code) {
    size_t h = size_t((unsigned long long)(code) * 0x9E3779B97F4A7C15ull >> 20) & (cap - 1);
    while (slots[h] != -1 && slots[h] != code) h = (h + 1) & (cap - 1);
    return h;
  };
  for (const auto& f : facets)
    for (const auto& p : f.loop)
      if (const size_t h = slot(p.first * nb + p.second); slots[h] == -1) slots[h] = p.first * nb + p.second, distinct.push_back(slots[h]);
  start.assign(a.size() + 1, 0);
  for (long long code : distinct) ++start[code / nb + 1];
  for (size_t i = 0; i < a.size(); ++i) start[i + 1] += start[i];
  fill.assign(start.begin(), start.end() - 1);
  out.vertices.resize(distinct.size());
  for (long long code : distinct) {
    const int i = int(code / nb), j = int(code % nb);
    // Within one i, insertion by j (a vertex of A meets a few of B).
    int k = fill[i]++;
    for (; k > start[i] && out.vertices[k - 1].j > j; --k) out.vertices[k] = out.vertices[k - 1];
    out.vertices[k] = SumVertex{i, j, a[i] + b[j]};
  }
  for (int v = 0; v < int(out.vertices.size()); ++v) number[slot(out.vertices[v].i * nb + out.vertices[v].j)] = v;
  for (const FacetLoop& f : facets) {
    SumPlane plane{f.normal.normalized(), -std::numeric_limits<double>::infinity(), f.loop[0].first, f.loop[0].second};
    for (const auto& p : f.loop) {
      out.loop_vertex.push_back(number[slot(p.first * nb + p.second)]);
      // The offset is the largest over the facet's vertices, so no vertex is ever cut off.
      plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[out.loop_vertex.back()].point));
    }
    out.loop_start.push_back(int(out.loop_vertex.size()));
    out.planes.push_back(plane);
  }
  out.V = int(out.vertices.size());
  out.E = int(out.loop_vertex.size() / 2);
  out.F = int(facets.size());
  out.euler_ok = out.F >= 4 && out.V - out.E + out.F == 2 && closed_manifold(out);
}

Status hull_corrector(const std::vector<Vector3d>& a, const std::vector<Vector3d>& b, MinkowskiSum& out) {
  const int nb = int(b.size());
  std::vector<Vector3d> sums;
  for (const auto& va : a)
    for (const auto& vb : b) sums.push_back(va + vb);
  std::vector<HullFacet> hull;
  if (!qhull_facets(sums, hull)) return Status::HullFailed;
  std::vector<FacetLoop> facets;
  for (const auto& h : hull) {
    FacetLoop f{h.normal, {}};
    for (int k : h.loop) f.loop.emplace_back(k / nb, k % nb);
    facets.push_back(std::move(f));
  }
  assemble(a, b, facets, out);
  out.corrected = true;
  // Qhull's facets of a badly scaled input (1e11 next to 1e-304) can fail to close
  // into a manifold: a clear error rather than an inconsistent "Ok".
  return out.euler_ok ? Status::Ok : Status::HullFailed;
}

}  // namespace detail

}  // namespace minksum
