// Convex hulls of point sets, the step that builds a shape from points:
//   Hull/<input>/minksum   the library's exact quickhull (kernels/core/hull.hpp): merged facets
//                          with their loops counter-clockwise and unit normals
//   Hull/<input>/qhull     libqhull_r: merged facets (to its tolerance) with their loops ordered
//   Hull/<input>/cgal      CGAL convex_hull_3 on Epick (exact predicates): a Surface_mesh of
//                          triangles, coplanar ones not merged
// on the Table 1 operands (cube, icosahedron, dodecahedron) and their pairwise sums (64 to
// 400 points), n points on a sphere (n = 8 ... 4,096), random clouds of 10^5 points in a cube
// and in a ball, and ten CAD parts of libcgal-demo (their vertex lists as given). Every row
// carries `facets` (for cgal, its triangles).
// Shape/<operand>/from_points: shape_from_points on a Table 1 operand, the public path (input
// checks, duplicates, the hull, the Gauss map), to set against the same row of an older build.
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <random>
#include <string>

#include "core/hull.hpp"
#include "support/cgal_peer.hpp"
#include "support/mesh_io.hpp"
#include "support/qhull_peer.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Vector3d;

void Minksum(benchmark::State& state, const std::vector<Vector3d>& points) {
  detail::HullFacets facets;
  for (auto _ : state) {
    if (!detail::convex_hull(points, facets)) state.SkipWithError("the hull failed");
    benchmark::DoNotOptimize(facets.index.data());
  }
  state.counters["facets"] = facets.count();
}

void Qhull(benchmark::State& state, const std::vector<Vector3d>& points) {
  std::vector<peers::QhullFacet> facets;
  for (auto _ : state) {
    if (!peers::qhull_facets(points, facets)) state.SkipWithError("Qhull failed");
    benchmark::DoNotOptimize(facets.data());
  }
  state.counters["facets"] = double(facets.size());
}

void Cgal(benchmark::State& state, const std::vector<Vector3d>& points) {
  const std::vector<Vector3d> origin{Vector3d::Zero()};
  int triangles = 0;
  for (auto _ : state) benchmark::DoNotOptimize(triangles = peers::cgal_quickhull(points, origin));
  state.counters["facets"] = triangles;
}

void FromPoints(benchmark::State& state, const std::vector<Vector3d>& points) {
  ConvexShape shape;
  for (auto _ : state) {
    if (shape_from_points(points, shape) != Status::Ok) state.SkipWithError("shape_from_points failed");
    benchmark::DoNotOptimize(&shape);
  }
}

void three_rows(const std::string& input, const std::vector<Vector3d>& points) {
  const std::string base = "Hull/" + input + "/";
  const auto unit = points.size() > 2000 ? benchmark::kMillisecond : benchmark::kMicrosecond;
  benchmark::RegisterBenchmark((base + "minksum").c_str(), Minksum, points)->Unit(unit);
  benchmark::RegisterBenchmark((base + "qhull").c_str(), Qhull, points)->Unit(unit);
  benchmark::RegisterBenchmark((base + "cgal").c_str(), Cgal, points)->Unit(unit);
}

// n points uniform in [-1, 1]^3, or in the unit ball.
std::vector<Vector3d> cloud(int n, bool ball, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  std::vector<Vector3d> p;
  while (int(p.size()) < n) {
    const Vector3d x(u(rng), u(rng), u(rng));
    if (!ball || x.squaredNorm() <= 1) p.push_back(x);
  }
  return p;
}

const int kRegistered = [] {
  const auto pairs = tools::table1_pairs();
  const std::pair<const char*, std::vector<Vector3d>> operands[] = {
      {"cube", pairs[0].a}, {"icosa", pairs[2].a}, {"dodeca", pairs[4].a}};
  for (const auto& [name, points] : operands) three_rows(name, points);
  for (const auto& pair : pairs) {
    std::vector<Vector3d> sums;
    for (const auto& p : pair.a)
      for (const auto& q : pair.b) sums.push_back(p + q);
    three_rows("sums_" + pair.name, sums);
  }
  for (int n = 8; n <= 4096; n *= 2) three_rows("sphere_" + std::to_string(n), tools::sphere_points(n, 7));
  three_rows("cube_cloud_100000", cloud(100000, false, 11));
  three_rows("ball_cloud_100000", cloud(100000, true, 13));
  for (const std::string& part : tools::cad_parts()) {
    std::vector<Vector3d> points;
    if (tools::cgal_demo_points(part, points)) three_rows(part.substr(0, part.find('.')), points);
  }
  for (const auto& [name, points] : operands)
    benchmark::RegisterBenchmark(("Shape/" + std::string(name) + "/from_points").c_str(), FromPoints, points)
        ->Unit(benchmark::kMicrosecond);
  return 0;
}();

}  // namespace
