// The public Minkowski sum and difference, the shared assembly of a result, and the corrector.
#include <algorithm>
#include <cmath>
#include <limits>

#include <minksum/kernels.hpp>

#include "hull.hpp"
#include "sum_internal.hpp"

namespace minksum {

using Eigen::Vector3d;

namespace detail {

void assemble(const ConvexPolytope& a, const ConvexPolytope& b, std::vector<FacetLoop>& facets,
              MinkowskiSum& out) {
  // The output's vectors keep their capacity (a caller that reuses `out` allocates once), and
  // the scratch tables are per thread: a sum allocates only while it grows.
  out.planes.clear(), out.vertices.clear();
  out.V = out.E = out.F = 0;
  out.euler_ok = out.corrected = false;
  thread_local std::vector<int> start, head, fill, number;
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
  // table of codes i |B| + j (linear probing; a dense |A| |B| table would make the sum
  // quadratic in the operands' sizes) and ordered by a counting sort on i.
  const long long nb = (long long)(b.vertices.size());
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
  start.assign(a.vertices.size() + 1, 0);
  for (long long code : distinct) ++start[code / nb + 1];
  for (size_t i = 0; i < a.vertices.size(); ++i) start[i + 1] += start[i];
  fill.assign(start.begin(), start.end() - 1);
  out.vertices.resize(distinct.size());
  for (long long code : distinct) {
    const int i = int(code / nb), j = int(code % nb);
    // Within one i, insertion by j (a vertex of A meets a few of B).
    int k = fill[i]++;
    for (; k > start[i] && out.vertices[k - 1].j > j; --k) out.vertices[k] = out.vertices[k - 1];
    out.vertices[k] = SumVertex{i, j, a.vertices[i] + b.vertices[j]};
  }
  for (int v = 0; v < int(out.vertices.size()); ++v) number[slot(out.vertices[v].i * nb + out.vertices[v].j)] = v;
  const auto index = [&](const std::pair<int, int>& p) { return number[slot(p.first * nb + p.second)]; };
  out.facets.resize(facets.size());
  size_t directed = 0;  // directed edges, one per loop step
  for (size_t k = 0; k < facets.size(); ++k) {
    const FacetLoop& f = facets[k];
    std::vector<int>& loop = out.facets[k];
    loop.clear();
    SumPlane plane{f.normal.normalized(), -std::numeric_limits<double>::infinity(),
                   f.loop[0].first, f.loop[0].second};
    for (const auto& p : f.loop) {
      loop.push_back(index(p));
      // The offset is the largest over the facet's vertices, so no vertex is ever cut off.
      plane.offset = std::max(plane.offset, plane.normal.dot(out.vertices[loop.back()].point));
    }
    directed += loop.size();
    out.planes.push_back(plane);
  }
  // A closed 2-manifold: every directed edge u -> v once, and v -> u once. Outgoing edges are
  // grouped per vertex (a few per vertex), so each check is a short scan.
  const size_t V = out.vertices.size();
  start.assign(V + 1, 0);
  head.resize(directed);
  for (const auto& loop : out.facets)
    for (int u : loop) ++start[u + 1];
  for (size_t v = 0; v < V; ++v) start[v + 1] += start[v];
  fill.assign(start.begin(), start.end() - 1);
  for (const auto& loop : out.facets)
    for (size_t k = 0; k < loop.size(); ++k) head[fill[loop[k]]++] = loop[(k + 1) % loop.size()];
  auto count = [&](int u, int v) {
    int n = 0;
    for (int k = start[u]; k < start[u + 1]; ++k) n += head[k] == v;
    return n;
  };
  bool manifold = true;
  for (size_t u = 0; u < V && manifold; ++u)
    for (int k = start[u]; k < start[u + 1] && manifold; ++k)
      manifold = count(int(u), head[k]) == 1 && count(head[k], int(u)) == 1;
  out.V = int(out.vertices.size());
  out.E = int(directed / 2);
  out.F = int(out.facets.size());
  out.euler_ok = manifold && out.F >= 4 && out.V - out.E + out.F == 2;
}

Status hull_corrector(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out) {
  const int nb = int(b.vertices.size());
  std::vector<Vector3d> sums;
  for (const auto& va : a.vertices)
    for (const auto& vb : b.vertices) sums.push_back(va + vb);
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
  // Qhull's facets of a badly scaled input (fuzzed: 1e11 next to 1e-304) can fail to close
  // into a manifold: a clear error rather than an inconsistent "Ok".
  return out.euler_ok ? Status::Ok : Status::HullFailed;
}

}  // namespace detail

namespace {

// Every facet's vertices (i, j) must be extreme along its normal in A and in B: a_i has no
// neighbour in A higher along n (local is global on a convex polytope), and so for b_j. A
// cheap proof that each plane supports A (+) B, which Euler's formula alone is not (a fuzzed
// needle-and-triangle pair once gave a consistent topology with a wrong plane).
bool planes_support(const ConvexPolytope& a, const ConvexPolytope& b, const MinkowskiSum& m) {
  // Neighbours of each vertex from the edges, in compressed lists (per-thread scratch).
  thread_local std::vector<int> start_a, list_a, start_b, list_b, fill;
  const auto neighbours = [](const ConvexPolytope& p, std::vector<int>& start, std::vector<int>& list) {
    start.assign(p.vertices.size() + 1, 0);
    for (const auto& e : p.edges) ++start[e.v0 + 1], ++start[e.v1 + 1];
    for (size_t v = 0; v < p.vertices.size(); ++v) start[v + 1] += start[v];
    list.resize(2 * p.edges.size());
    fill.assign(start.begin(), start.end() - 1);
    for (const auto& e : p.edges) list[fill[e.v0]++] = e.v1, list[fill[e.v1]++] = e.v0;
  };
  neighbours(a, start_a, list_a), neighbours(b, start_b, list_b);
  double size = 0;
  for (const auto* p : {&a, &b})
    for (const auto& v : p->vertices) size = std::max(size, v.cwiseAbs().maxCoeff());
  const double tol = 1e-12 * size;
  const auto extreme = [&](const ConvexPolytope& p, const std::vector<int>& start, const std::vector<int>& list,
                           int i, const Eigen::Vector3d& dir) {
    const double top = dir.dot(p.vertices[i]);
    for (int k = start[i]; k < start[i + 1]; ++k)
      if (dir.dot(p.vertices[list[k]]) > top + tol) return false;
    return true;
  };
  for (int f = 0; f < m.F; ++f)
    for (int v : m.facets[f]) {
      const auto& x = m.vertices[v];
      if (!extreme(a, start_a, list_a, x.i, m.planes[f].normal) ||
          !extreme(b, start_b, list_b, x.j, m.planes[f].normal))
        return false;
    }
  return true;
}

bool usable(const ConvexPolytope& p) {
  return p.vertices.size() >= 3 && p.faces.size() >= 2 && !p.edges.empty();
}

Status sum_dispatch(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out,
                    Method method) {
  if (method == Method::Kernel) method = Method::Fast;  // the kernel takes two boxes
  // An error leaves an empty result; a result reuses the capacity of `out` (see assemble).
  const auto fail = [&out](Status s) {
    out = MinkowskiSum{};
    return s;
  };
  out.method = method, out.corrected = false;
  if (!usable(a) || !usable(b)) return fail(Status::TooFewPoints);
  // Two coplanar flat operands have a flat sum; the result type describes solids only.
  if (a.flat && b.flat && a.faces[0].normal.cross(b.faces[0].normal).norm() <= 1e-12)
    return fail(Status::DegenerateResult);
  if (method == Method::Hull) {
    const Status s = detail::hull_corrector(a, b, out);
    out.corrected = false;  // the hull is the method here, not a correction
    return s;
  }
  // Small operands in general position: the certified bit-set path, whose every sign has a
  // margin, so it needs neither the Euler-and-support check below nor the corrector.
  if (method == Method::Fast && detail::sum_small(a, b, out)) return Status::Ok;
  bool ok = true;
  if (method == Method::Fast || method == Method::Kernel)
    ok = detail::sum_fast(a, b, out);
  else
    detail::sum_reference(a, b, out);
  // Section 3 of the paper: an inconsistent result (Euler fails, or a plane that does not
  // support the sum) is rebuilt from the hull.
  if (!ok || !out.euler_ok || !planes_support(a, b, out)) {
    const Status s = detail::hull_corrector(a, b, out);
    out.method = method;
    return s;
  }
  return Status::Ok;
}

// -B: vertices and normals negated; loops reversed so they stay counter-clockwise from outside.
ConvexPolytope negated(const ConvexPolytope& p) {
  ConvexPolytope n = p;
  for (auto& v : n.vertices) v = -v;
  for (auto& f : n.faces) {
    f.normal = -f.normal;
    std::reverse(f.loop.begin(), f.loop.end());
  }
  for (auto& e : n.edges) std::swap(e.left, e.right);
  return n;
}

}  // namespace

Status minkowski_sum(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out,
                     Method method) {
  return sum_dispatch(a, b, out, method);
}

Status minkowski_difference(const ConvexPolytope& a, const ConvexPolytope& b, MinkowskiSum& out,
                            Method method) {
  return sum_dispatch(a, negated(b), out, method);
}

Status minkowski_sum(const Box& a, const Box& b, MinkowskiSum& out) {
  for (const Box* x : {&a, &b})
    if (const Status s = check_box(*x); s != Status::Ok) {
      out = MinkowskiSum{};
      return s;
    }
  // The kernel's whole-polytope path on one lane: 30 planes and their vertex loops (symmetry
  // and index tracking; see box_box_sum), its buffers on the stack (about 26 KB).
  BoxBatch<double, kLaneMultiple> A, B;
  BoxBoxSum<double, kLaneMultiple> sum;
  A.set_one(a), B.set_one(b);
  box_box_sum(A, B, sum);
  // The 32 vertices: the pairs the loops visit, numbered in (i, j) order (bit 8 i + j).
  std::uint64_t used = 0;
  for (int p = 0; p < 30; ++p)
    for (int m = 0; m < 4; ++m) {
      const int v = int(sum.loop[p][0] >> (6 * m) & 63);
      used |= std::uint64_t(1) << (8 * (v & 7) + (v >> 3));
    }
  // Out of general position (parallel edges, three coplanar ones) facets merge, and the loops
  // are not meaningful: the general path.
  if (!sum.general[0] || __builtin_popcountll(used) != 32) {
    ConvexPolytope pa, pb;  // vertex k is box_corner(k), as the kernel's codes number them
    polytope_from_box(a, pa), polytope_from_box(b, pb);
    return minkowski_sum(pa, pb, out, Method::Fast);
  }
  int number[64];
  out.vertices.resize(32);
  Vector3d corner_a[8], corner_b[8];
  for (int k = 0; k < 8; ++k) corner_a[k] = box_corner(a, k), corner_b[k] = box_corner(b, k);
  int v = 0;
  for (std::uint64_t m = used; m; m &= m - 1, ++v) {
    const int bit = __builtin_ctzll(m), i = bit >> 3, j = bit & 7;
    number[bit] = v;
    out.vertices[v] = SumVertex{i, j, corner_a[i] + corner_b[j]};
  }
  // Facet p < 15 has axis p's plane, p + 15 the opposite one; each loop starts at its smallest
  // pair (the support corners with the facet's edge bits clear), as assemble's do, and the
  // plane's pair is that one; the offsets are the kernel's support function h_A(n) + h_B(n).
  out.planes.resize(30), out.facets.resize(30);
  for (int p = 0; p < 30; ++p) {
    const int q = p % 15;
    std::vector<int>& loop = out.facets[p];
    loop.resize(4);
    for (int m = 0; m < 4; ++m) {
      const int code = int(sum.loop[p][0] >> (6 * m) & 63);
      loop[m] = number[8 * (code & 7) + (code >> 3)];
    }
    SumPlane& plane = out.planes[p];
    plane.normal = (p < 15 ? 1.0 : -1.0) * Vector3d(sum.planes.n[q][0][0], sum.planes.n[q][1][0], sum.planes.n[q][2][0]);
    plane.offset = sum.planes.offset[p][0];
    plane.i = out.vertices[loop[0]].i, plane.j = out.vertices[loop[0]].j;
  }
  out.V = 32, out.E = 60, out.F = 30;
  out.euler_ok = true;
  out.corrected = false;
  out.method = Method::Kernel;
  return Status::Ok;
}

}  // namespace minksum
