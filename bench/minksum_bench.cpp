// Google Benchmark comparison of the object-space method against quickhull (Qhull) on the
// paper's Table 1 pairs (B under tools::table1_rotation()). Every method outputs the full
// polytope, facets and vertices:
//   osm_fast       minkowski_sum, Method::Fast: planes with support pairs, vertices, facet loops
//   osm_reference  minkowski_sum, Method::Reference: the same output, by the paper's plane push
//   qhull          libqhull_r on the |A||B| pairwise sums: merged facets (unit normal) with their
//                  vertex loops ordered counter-clockwise (the pairwise sums are formed inside
//                  the timed loop, as a user of the convex hull method must)
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include "hull.hpp"
#include "tools/shapes.hpp"

namespace {

using namespace minksum;

struct Prepared {
  tools::Table1Pair pair;
  ConvexPolytope A, B;
};

Prepared prepare(int row) {
  Prepared p{tools::table1_pairs()[row], {}, {}};
  polytope_from_points(p.pair.a, p.A);
  polytope_from_points(p.pair.b, p.B);
  return p;
}

void Table1Osm(benchmark::State& state, int row, Method method) {
  const Prepared p = prepare(row);
  MinkowskiSum m;
  for (auto _ : state) {
    minkowski_sum(p.A, p.B, m, method);
    benchmark::DoNotOptimize(m.planes.data());
  }
  state.counters["facets"] = m.F;
  state.counters["vertices"] = m.V;
}

void Table1Qhull(benchmark::State& state, int row) {
  const Prepared p = prepare(row);
  std::vector<detail::HullFacet> facets;
  std::vector<Eigen::Vector3d> sums;
  for (auto _ : state) {
    sums.clear();
    for (const auto& a : p.A.vertices)
      for (const auto& b : p.B.vertices) sums.push_back(a + b);
    detail::qhull_facets(sums, facets);
    benchmark::DoNotOptimize(facets.data());
  }
  state.counters["facets"] = double(facets.size());
}

const int kRegistered = [] {
  const auto pairs = tools::table1_pairs();
  for (int row = 0; row < int(pairs.size()); ++row) {
    const std::string base = "Table1/" + pairs[row].name + "/";
    benchmark::RegisterBenchmark((base + "osm_reference").c_str(), Table1Osm, row, Method::Reference)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "osm_fast").c_str(), Table1Osm, row, Method::Fast)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "qhull").c_str(), Table1Qhull, row)
        ->Unit(benchmark::kMicrosecond);
  }
  return 0;
}();

}  // namespace

BENCHMARK_MAIN();
