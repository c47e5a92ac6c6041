// Queries against FCL 0.7 on the same seeded poses: BoxBoxDistance/<method>,
// BoxBoxPenetration/<method>, BoxTriangleDistance/<method>, TriangleTriangleDistance/<method>
// (every other pair overlapping; minksum answers penetration there, FCL's distance call only
// reports the collision), PolytopeDistance/<pair>/<method> and PolytopePenetration/<pair>/<method>
// (one separated and one overlapping pose of each Table 1 pair, and of two hulls of 64 and of
// 256 points on a sphere). minksum skips the farthest pair (Want::Witnesses) as FCL has none,
// except in BoxBoxDistance/minksum_with_max. Distance runs use 256 box pairs, half of them
// overlapping; penetration runs use overlapping pairs only. IsaKernels/box_box_query_single,
// box_box_distance_1024 and triangle_distance_256 run the same bodies on every ISA.
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <memory>
#include <random>

#include "support/fcl_peer.hpp"
#include "isa_rows.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Vector3d;

// Seeded box pairs; `overlapping` of every 2 overlap (checked with minksum's exact answer).
std::vector<std::pair<Box, Box>> poses(int n, bool only_overlapping) {
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> u(-1, 1), h(0.2, 1);
  std::vector<std::pair<Box, Box>> out;
  while (int(out.size()) < n) {
    Box a, b;
    for (Box* x : {&a, &b}) {
      x->rotation = tools::axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3 * u(rng));
      x->half_extents = Vector3d(h(rng), h(rng), h(rng));
    }
    b.center = 2.2 * Vector3d(u(rng), u(rng), u(rng));
    Proximity p;
    proximity(a, b, p);
    const bool want_overlap = only_overlapping || out.size() % 2 == 0;
    if (p.intersecting == want_overlap) out.emplace_back(a, b);
  }
  return out;
}

// Distance with closest points, or depth and direction (what FCL's calls return), or (want =
// Want::All) the maximum distance as well.
void BoxDistanceMinksum(benchmark::State& state, Want want) {
  const auto ps = poses(256, false);
  Proximity p;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = ps[k++ & 255];
    proximity(a, b, p, want);
    benchmark::DoNotOptimize(p.distance);
  }
}

void BoxDistanceFcl(benchmark::State& state, peers::FclSolver solver) {
  const auto ps = poses(256, false);
  peers::FclPair pair(ps[0].first, ps[0].second);
  peers::FclAnswer answer;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = ps[k++ & 255];
    pair.set_boxes(a, b);
    pair.proximity(solver, answer);  // nearest points, and the depth on contact, as minksum gives
    benchmark::DoNotOptimize(answer.distance);
  }
}

void BoxPenetrationMinksum(benchmark::State& state) {
  const auto ps = poses(256, true);
  Proximity p;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = ps[k++ & 255];
    proximity(a, b, p, Want::Witnesses);
    benchmark::DoNotOptimize(p.penetration_depth);
  }
}

void BoxPenetrationFcl(benchmark::State& state) {
  const auto ps = poses(256, true);
  peers::FclPair pair(ps[0].first, ps[0].second);
  peers::FclAnswer answer;
  size_t k = 0;
  for (auto _ : state) {
    const auto& [a, b] = ps[k++ & 255];
    pair.set_boxes(a, b);
    pair.penetration(peers::FclSolver::Gjk, answer);
    benchmark::DoNotOptimize(answer.depth);
  }
}

// The batched kernel over the same 256 poses, four times over (1024 lanes): time per pair, in
// float (minksum_batch) and double (minksum_batch_double).
template <class T>
void BoxDistanceBatch(benchmark::State& state) {
  const auto ps = poses(256, false);
  auto A = std::make_unique<BoxBatch<T, 1024>>(), B = std::make_unique<BoxBatch<T, 1024>>();
  auto out = std::make_unique<BoxBoxProximity<T, 1024>>();
  for (int k = 0; k < 1024; ++k) A->set(k, ps[k & 255].first), B->set(k, ps[k & 255].second);
  A->count = B->count = 1024;
  for (auto _ : state) {
    box_box_proximity(*A, *B, *out);
    benchmark::DoNotOptimize(out->distance[1023]);
  }
  state.SetItemsProcessed(state.iterations() * 1024);
}

// The fused separating-axis kernel (collision and a distance lower bound), per pair.
void BoxSeparationBatch(benchmark::State& state) {
  const auto ps = poses(256, false);
  auto A = std::make_unique<BoxBatch<float, 1024>>(), B = std::make_unique<BoxBatch<float, 1024>>();
  auto out = std::make_unique<BoxBoxSeparation<float, 1024>>();
  for (int k = 0; k < 1024; ++k) A->set(k, ps[k & 255].first), B->set(k, ps[k & 255].second);
  A->count = B->count = 1024;
  for (auto _ : state) {
    box_box_separation(*A, *B, *out);
    benchmark::DoNotOptimize(out->bound[1023]);
  }
  state.SetItemsProcessed(state.iterations() * 1024);
}

// Seeded box-triangle (or, with two_triangles, triangle-triangle) pairs, every other one
// overlapping; 256 of them, each with its FCL pair built once.
struct SmallPairs {
  std::vector<Box> boxes;
  std::vector<Triangle> s, t;
  std::vector<std::unique_ptr<peers::FclPair>> fcl;
};

SmallPairs small_pairs(bool two_triangles) {
  std::mt19937_64 rng(43);
  SmallPairs out;
  while (out.t.size() < 256) {
    const Box box = tools::random_box(rng, 1.5);
    const Triangle s = tools::random_triangle(rng, 1.2), t = tools::random_triangle(rng, 1.2);
    Proximity p;
    if ((two_triangles ? proximity(s, t, p) : proximity(box, t, p)) != Status::Ok) continue;
    if (p.intersecting != (out.t.size() % 2 == 0)) continue;
    out.boxes.push_back(box), out.s.push_back(s), out.t.push_back(t);
    out.fcl.push_back(two_triangles ? std::make_unique<peers::FclPair>(s, t)
                                    : std::make_unique<peers::FclPair>(box, t));
  }
  return out;
}

void SmallDistance(benchmark::State& state, bool two_triangles, bool fcl) {
  const SmallPairs ps = small_pairs(two_triangles);
  Proximity p;
  peers::FclAnswer answer;
  size_t k = 0;
  for (auto _ : state) {
    const size_t i = k++ & 255;
    if (fcl) {
      ps.fcl[i]->proximity(peers::FclSolver::Gjk, answer);
      benchmark::DoNotOptimize(answer.distance);
    } else {
      if (two_triangles)
        proximity(ps.s[i], ps.t[i], p, Want::Witnesses);
      else
        proximity(ps.boxes[i], ps.t[i], p, Want::Witnesses);
      benchmark::DoNotOptimize(p.distance);
    }
  }
}

// The exact triangle-triangle distance alone (no penetration, no max distance), as the octree
// calls it: the scalar path one pair at a time, and the batched kernel (the active ISA), per
// pair, over the same 256 pairs.
void TriangleDistanceOnly(benchmark::State& state, bool batched) {
  const SmallPairs ps = small_pairs(true);
  if (!batched) {
    size_t k = 0;
    Vector3d pa, pb;
    for (auto _ : state) {
      const size_t i = k++ & 255;
      const Vector3d a[3] = {ps.s[i].a, ps.s[i].b, ps.s[i].c}, b[3] = {ps.t[i].a, ps.t[i].b, ps.t[i].c};
      benchmark::DoNotOptimize(triangle_distance(a, b, pa, pb));
    }
    return;
  }
  auto S = std::make_unique<TriangleBatch<double, 256>>(), T = std::make_unique<TriangleBatch<double, 256>>();
  auto out = std::make_unique<TriangleDistances<double, 256>>();
  for (int k = 0; k < 256; ++k) S->set(k, ps.s[k]), T->set(k, ps.t[k]);
  S->count = T->count = 256;
  for (auto _ : state) {
    triangle_distance(*S, *T, *out);
    benchmark::DoNotOptimize(out->distance[255]);
  }
  state.SetItemsProcessed(state.iterations() * 256);
}

// Two polytopes, B moved clear of A (distance) or into it (penetration: minksum's depth,
// direction and witness points; FCL's collide with one contact): a Table 1 pair (row >= 0), or
// hulls of n seeded points on the unit sphere (row < 0, n = -row).
void PolytopeQuery(benchmark::State& state, int row, bool fcl, bool overlapping) {
  std::vector<Vector3d> a, b;
  if (row >= 0) {
    const auto pair = tools::table1_pairs()[row];
    a = pair.a, b = pair.b;
  } else {
    a = tools::sphere_points(-row, 1), b = tools::sphere_points(-row, 2);
  }
  const Vector3d shift = overlapping ? Vector3d(0.9, 0.3, 0.2) : Vector3d(4.5, 0.3, 0.2);
  for (auto& p : b) p += shift;
  ConvexPolytope A, B;
  polytope_from_points(a, A);
  polytope_from_points(b, B);
  Proximity p;
  if (proximity(A, B, p) != Status::Ok || p.intersecting != overlapping) {
    state.SkipWithError("the pose is not what the benchmark says");
    return;
  }
  if (fcl) {
    peers::FclPair peer(A, B);
    peers::FclAnswer answer;
    for (auto _ : state) {
      if (overlapping)
        peer.penetration(peers::FclSolver::Gjk, answer);
      else
        peer.proximity(peers::FclSolver::Gjk, answer);
      benchmark::DoNotOptimize(answer.depth);
    }
  } else {
    for (auto _ : state) {
      proximity(A, B, p, Want::Witnesses);
      benchmark::DoNotOptimize(p.distance);
    }
  }
}

const int kRegistered = [] {
  benchmark::RegisterBenchmark("BoxBoxDistance/minksum", BoxDistanceMinksum, Want::Witnesses);
  benchmark::RegisterBenchmark("BoxBoxDistance/minksum_with_max", BoxDistanceMinksum, Want::All);
  benchmark::RegisterBenchmark("BoxBoxDistance/fcl_gjk", BoxDistanceFcl, peers::FclSolver::Gjk);
  benchmark::RegisterBenchmark("BoxBoxDistance/fcl_libccd", BoxDistanceFcl, peers::FclSolver::Libccd);
  benchmark::RegisterBenchmark("BoxBoxDistance/minksum_batch", BoxDistanceBatch<float>);
  benchmark::RegisterBenchmark("BoxBoxDistance/minksum_batch_double", BoxDistanceBatch<double>);
  benchmark::RegisterBenchmark("BoxBoxSeparation/minksum_batch", BoxSeparationBatch);
  benchmark::RegisterBenchmark("BoxBoxPenetration/minksum", BoxPenetrationMinksum);
  benchmark::RegisterBenchmark("BoxBoxPenetration/fcl_gjk", BoxPenetrationFcl);
  benchmark::RegisterBenchmark("BoxTriangleDistance/minksum", SmallDistance, false, false);
  benchmark::RegisterBenchmark("BoxTriangleDistance/fcl_gjk", SmallDistance, false, true);
  benchmark::RegisterBenchmark("TriangleTriangleDistance/minksum", SmallDistance, true, false);
  benchmark::RegisterBenchmark("TriangleTriangleDistance/fcl_gjk", SmallDistance, true, true);
  benchmark::RegisterBenchmark("TriangleExactDistance/scalar", TriangleDistanceOnly, false);
  benchmark::RegisterBenchmark("TriangleExactDistance/batch", TriangleDistanceOnly, true);
  // The same kernels on every ISA (the report's per-ISA table).
  bench::register_per_isa("box_box_query_single", "double",
                          [](benchmark::State& state) { BoxDistanceMinksum(state, Want::Witnesses); });
  bench::register_per_isa("box_box_distance_1024", "float", BoxDistanceBatch<float>);
  bench::register_per_isa("box_box_distance_1024", "double", BoxDistanceBatch<double>);
  bench::register_per_isa("triangle_distance_256", "double",
                          [](benchmark::State& state) { TriangleDistanceOnly(state, true); });
  const auto pairs = tools::table1_pairs();
  std::vector<int> rows = {-256, -64};  // the sphere hulls, then the Table 1 rows
  for (int row = 0; row < int(pairs.size()); ++row) rows.push_back(row);
  for (const int row : rows) {
    const std::string name = row >= 0 ? pairs[row].name : "sphere" + std::to_string(-row);
    for (const bool overlapping : {false, true}) {
      const std::string base = (overlapping ? "PolytopePenetration/" : "PolytopeDistance/") + name + "/";
      benchmark::RegisterBenchmark((base + "minksum").c_str(), PolytopeQuery, row, false, overlapping)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark((base + "fcl_gjk").c_str(), PolytopeQuery, row, true, overlapping)
          ->Unit(benchmark::kMicrosecond);
    }
  }
  return 0;
}();

}  // namespace
