// Google Benchmark runs of the SoA kernels on every supported ISA, with Qhull on the same box
// pair as the peer: IsaKernels/box_box_planes_<batch>/<precision>/<isa>,
// IsaKernels/box_triangle_planes_<batch>/float/<isa>, IsaKernels/support_push_<n>/float/<isa>,
// BoxBox/single, BoxBox/qhull, TopologyInstantiate/<kind>. Items are box pairs (or facets, or
// directions).
#include <benchmark/benchmark.h>
#include <minksum/kernels.hpp>
#include <minksum/sum.hpp>

#include <memory>
#include <random>

#include "support/qhull_peer.hpp"
#include "isa_rows.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Vector3d;

template <class T, int N>
void BoxBoxBatch(benchmark::State& state) {
  auto a = std::make_unique<BoxBatch<T, N>>(), b = std::make_unique<BoxBatch<T, N>>();
  auto out = std::make_unique<BoxBoxPlanes<T, N>>();
  std::mt19937_64 rng(1);
  a->count = b->count = N;
  for (int k = 0; k < N; ++k) a->set(k, tools::random_box(rng, 5, 2)), b->set(k, tools::random_box(rng, 5, 2));
  for (auto _ : state) {
    box_box_planes(*a, *b, true, *out);
    benchmark::DoNotOptimize(out->offset[29][N - 1]);
  }
  state.SetItemsProcessed(state.iterations() * N);
}

template <int N>
void BoxTriangleBatch(benchmark::State& state) {
  auto a = std::make_unique<BoxBatch<float, N>>();
  auto t = std::make_unique<TriangleBatch<float, N>>();
  auto out = std::make_unique<BoxTrianglePlanes<float, N>>();
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1, 1);
  a->count = t->count = N;
  for (int k = 0; k < N; ++k) {
    a->set(k, tools::random_box(rng, 5, 2));
    t->set(k, Triangle{{u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}, {u(rng), u(rng), u(rng)}});
  }
  for (auto _ : state) {
    box_triangle_planes(*a, *t, true, *out);
    benchmark::DoNotOptimize(out->offset[25][N - 1]);
  }
  state.SetItemsProcessed(state.iterations() * N);
}

void SupportPushBench(benchmark::State& state, int n) {
  const auto pts = tools::sphere_points(n, 3), dirs = tools::sphere_points(64, 4);
  std::vector<float> x, y, z, dx, dy, dz, best(64);
  std::vector<int> arg(64);
  for (const auto& p : pts) x.push_back(float(p.x())), y.push_back(float(p.y())), z.push_back(float(p.z()));
  for (const auto& d : dirs) dx.push_back(float(d.x())), dy.push_back(float(d.y())), dz.push_back(float(d.z()));
  for (auto _ : state) {
    support_push(x.data(), y.data(), z.data(), n, dx.data(), dy.data(), dz.data(), 64, best.data(), arg.data());
    benchmark::DoNotOptimize(arg.data());
  }
  state.SetItemsProcessed(state.iterations() * 64);  // directions
}

void BoxBoxSingle(benchmark::State& state) {
  std::mt19937_64 rng(5);
  const Box a = tools::random_box(rng, 5, 2), b = tools::random_box(rng, 5, 2);
  BoxBoxPair out;
  for (auto _ : state) {
    box_box_planes(a, b, true, out);
    benchmark::DoNotOptimize(out.offset[1][14]);
  }
  state.SetItemsProcessed(state.iterations());
}

// The peer: Qhull on the 64 pairwise sums of one box pair (a full merged polytope).
void BoxBoxQhull(benchmark::State& state) {
  std::mt19937_64 rng(5);
  const Box a = tools::random_box(rng, 5, 2), b = tools::random_box(rng, 5, 2);
  ConvexPolytope pa, pb;
  polytope_from_box(a, pa);
  polytope_from_box(b, pb);
  std::vector<Vector3d> sums;
  std::vector<peers::QhullFacet> facets;
  for (auto _ : state) {
    sums.clear();
    for (const auto& p : pa.vertices)
      for (const auto& q : pb.vertices) sums.push_back(p - q);
    peers::qhull_facets(sums, facets);
    benchmark::DoNotOptimize(facets.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void TopologyInstantiate(benchmark::State& state, int kind) {
  TopologyTable t;
  std::mt19937_64 rng(6);
  const Box a = tools::random_box(rng, 5, 2), b = tools::random_box(rng, 5, 2);
  if (kind == 0) {  // box-box
    auto A = std::make_unique<BoxBatch<double, 16>>(), B = std::make_unique<BoxBatch<double, 16>>();
    auto out = std::make_unique<BoxBoxPlanes<double, 16>>();
    A->count = B->count = 1;
    A->set(0, a), B->set(0, b);
    A->pad(), B->pad();
    box_box_planes(*A, *B, true, *out);
    t = topology_table(*out, 0, a, b, true);
  } else {  // general: icosahedron (-) dodecahedron
    const auto pair = tools::table1_pairs()[5];
    ConvexPolytope A, B;
    polytope_from_points(pair.a, A);
    polytope_from_points(pair.b, B);
    MinkowskiSum m;
    minkowski_difference(A, B, m);
    t = topology_table(m, A, B, true);
  }
  std::vector<double> offsets(t.nx.size());
  double s = 1;
  for (auto _ : state) {
    instantiate(t, s, Vector3d(1, 2, 3), 0.5 * s, Vector3d(-1, 0, 2), offsets.data());
    benchmark::DoNotOptimize(offsets.data());
    s = s == 1 ? 0.5 : 1;
  }
  state.SetItemsProcessed(state.iterations() * int64_t(t.nx.size()));  // facets
}

const int kRegistered = [] {
  using bench::register_per_isa;
  register_per_isa("box_box_planes_16", "float", BoxBoxBatch<float, 16>);
  register_per_isa("box_box_planes_1024", "float", BoxBoxBatch<float, 1024>);
  register_per_isa("box_box_planes_65536", "float", BoxBoxBatch<float, 65536>);
  register_per_isa("box_box_planes_1024", "double", BoxBoxBatch<double, 1024>);
  register_per_isa("box_triangle_planes_16", "float", BoxTriangleBatch<16>);
  register_per_isa("box_triangle_planes_1024", "float", BoxTriangleBatch<1024>);
  register_per_isa("box_triangle_planes_65536", "float", BoxTriangleBatch<65536>);
  for (int n : {8, 64, 512, 4096})
    register_per_isa("support_push_" + std::to_string(n), "float",
                     [n](benchmark::State& state) { SupportPushBench(state, n); });
  benchmark::RegisterBenchmark("BoxBox/single", BoxBoxSingle);
  benchmark::RegisterBenchmark("BoxBox/qhull", BoxBoxQhull);
  benchmark::RegisterBenchmark("TopologyInstantiate/box_box", TopologyInstantiate, 0);
  benchmark::RegisterBenchmark("TopologyInstantiate/general", TopologyInstantiate, 1);
  return 0;
}();

}  // namespace
