// Batches (minksum/parallel.hpp) on 1 and 2 threads, wall-clock time per batch:
//   Batch/<proximity|time_of_impact|mesh_distance|sum>/threads:<1|2>
// The workloads are the ones bench/python_bench.py runs from Python (defined the same way there),
// so that REPORT.md sets the Python figures beside these C++ ones from the same report run:
//   proximity       a box (half 0.5) and an icosahedron at 100,000 poses along an orbit
//   time_of_impact  a sphere (0.3) falling from 3 above to 3 below a box (half 1), 20,000 motions
//   mesh_distance   a sphere (0.3) over a bumpy 64 x 64 sheet (8,192 triangles), 20,000 poses
//   sum             the box (+) the icosahedron at 5,000 poses
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>
#include <minksum/parallel.hpp>

#include <cmath>
#include <vector>

namespace {

using namespace minksum;
using Eigen::Isometry3d;
using Eigen::Vector3d;

// n poses along an orbit round the origin, turning about z, `lift` above it.
std::vector<Isometry3d> orbit(long n, double lift) {
  std::vector<Isometry3d> poses(size_t(n), Isometry3d::Identity());
  for (long k = 0; k < n; ++k) {
    const double t = double(k) / double(n);
    poses[size_t(k)].linear() = Eigen::AngleAxisd(9 * t, Vector3d::UnitZ()).toRotationMatrix();
    poses[size_t(k)].translation() = Vector3d(2.5 * std::cos(40 * t), 2.5 * std::sin(30 * t), lift + 0.4 * std::sin(7 * t));
  }
  return poses;
}

struct Workloads {
  ConvexShape box, unit_box, icosahedron, ball;
  Octree sheet;
  Workloads() {
    Box b;
    b.half_extents = Vector3d::Constant(0.5);
    shape_from_box(b, box);
    shape_from_box(Box{}, unit_box);
    const double phi = (1 + std::sqrt(5.0)) / 2;
    std::vector<Vector3d> ico;
    for (double s : {-1.0, 1.0})
      for (double u : {-phi, phi}) ico.insert(ico.end(), {{0, s, u}, {s, u, 0}, {u, 0, s}});
    shape_from_points(ico, icosahedron);
    shape_from_sphere(0.3, ball);
    std::vector<Vector3d> v;
    std::vector<std::array<int, 3>> t;
    for (int i = 0; i <= 64; ++i)
      for (int j = 0; j <= 64; ++j) {
        const double x = -4 + 0.125 * i, y = -4 + 0.125 * j;
        v.emplace_back(x, y, 0.2 * std::sin(0.5 * x + y));
      }
    for (int i = 0; i < 64; ++i)
      for (int j = 0; j < 64; ++j) {
        const int c = i * 65 + j;
        t.push_back({c, c + 65, c + 1}), t.push_back({c + 1, c + 65, c + 66});
      }
    build_octree(v, t, sheet);
  }
};

const Workloads& workloads() {
  static const Workloads w;
  return w;
}

const Isometry3d kHere = Isometry3d::Identity();

void report(benchmark::State& state, long n, const BatchStatus& s) {
  if (s.status != Status::Ok) state.SkipWithError(to_string(s.status));
  state.SetItemsProcessed(state.iterations() * n);
}

void BatchProximity(benchmark::State& state) {
  const Workloads& w = workloads();
  const long n = 100000;
  const std::vector<Isometry3d> poses = orbit(n, 0);
  std::vector<Proximity> out(static_cast<size_t>(n));
  BatchStatus s;
  for (auto _ : state)
    s = proximity_batch(w.box, {&kHere, 1}, w.icosahedron, {poses.data(), n}, n, out.data(), Want::Witnesses, {int(state.range(0))});
  report(state, n, s);
}

void BatchTimeOfImpact(benchmark::State& state) {
  const Workloads& w = workloads();
  const long n = 20000;
  const std::vector<Isometry3d> from = orbit(n, 3), to = orbit(n, -3);
  std::vector<TimeOfImpact> out(static_cast<size_t>(n));
  BatchStatus s;
  for (auto _ : state)
    s = time_of_impact_batch(w.unit_box, {&kHere, 1}, {&kHere, 1}, w.ball, {from.data(), n}, {to.data(), n}, n, out.data(), 0,
                             {int(state.range(0))});
  report(state, n, s);
}

void BatchMeshDistance(benchmark::State& state) {
  const Workloads& w = workloads();
  const long n = 20000;
  const std::vector<Isometry3d> poses = orbit(n, 1);
  std::vector<MeshDistance> out(static_cast<size_t>(n));
  BatchStatus s;
  for (auto _ : state) s = mesh_distance_batch(w.sheet, {&kHere, 1}, w.ball, {poses.data(), n}, n, out.data(), {int(state.range(0))});
  report(state, n, s);
}

void BatchSum(benchmark::State& state) {
  const Workloads& w = workloads();
  const long n = 5000;
  const std::vector<Isometry3d> poses = orbit(n, 0);
  const std::vector<ConvexShape> a(static_cast<size_t>(n), w.box), b(static_cast<size_t>(n), w.icosahedron);
  std::vector<MinkowskiSum> out(static_cast<size_t>(n));
  BatchStatus s;
  for (auto _ : state)
    s = minkowski_sum_batch(a.data(), {&kHere, 1}, b.data(), {poses.data(), n}, n, out.data(), false, SumParts::Whole,
                            {int(state.range(0))});
  report(state, n, s);
}

}  // namespace

BENCHMARK(BatchProximity)->Name("Batch/proximity")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BatchTimeOfImpact)->Name("Batch/time_of_impact")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BatchMeshDistance)->Name("Batch/mesh_distance")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BatchSum)->Name("Batch/sum")->ArgName("threads")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
