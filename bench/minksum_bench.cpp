// Google Benchmark comparison of the object-space method against quickhull (Qhull) on the
// paper's Table 1 pairs (tools::table1_pairs(): exact coordinates, B turned by a rational
// quaternion). Every method outputs the full polytope, facets and vertices:
//   osm_prepared   minkowski_sum of two ConvexShapes prepared once in their body frames, B's
//                  rotation passed as its pose and applied inside the timed call
//   osm_planes     the same sum at SumParts::Planes: planes with support pairs only (what a
//                  query or a C-space obstacle needs; no vertices nor loops)
//   osm_fast       minkowski_sum, Method::Fast on ConvexPolytopes (prepared inside every call):
//                  planes with support pairs, vertices, facet loops
//   osm_reference  minkowski_sum, Method::Reference: the same output, by the paper's plane push
//   osm_kernel     box_box_sum (cube_rotcube only), double: the box-box kernel's whole polytope
//                  per lane, 30 planes with support corners, 30 vertex loops and the corners
//                  the 32 vertices pair; time per sum, 32 lanes per call (the SoA kernel's use)
//   osm_kernel_float   the same in float
//   osm_kernel_single  minkowski_sum of two Boxes: the kernel for one pair, assembled into a
//                  MinkowskiSum (vectors of planes, loops and vertices) and checked
//                  (the three kernel rows on every ISA: IsaKernels/box_box_sum_*, isa_rows.hpp)
//   qhull          libqhull_r on the |A||B| pairwise sums: merged facets (unit normal) with their
//                  vertex loops ordered counter-clockwise (the pairwise sums are formed inside
//                  the timed loop, as a user of the convex hull method must)
//   cgal_quickhull CGAL convex_hull_3 (Epick) on the pairwise sums, formed in the loop too: a
//                  Surface_mesh of triangles (coplanar triangles not merged)
//   cgal_nef       CGAL minkowski_sum_3 on Nef polyhedra (Epeck): the exact sum, from Nef
//                  operands built before the loop (as the prepared row's shapes are)
//   bullet_hull    Bullet's btConvexHullComputer on the pairwise sums (formed in the loop):
//                  planar n-gon faces with half-edges, what a game or robotics user reaches for
// Degenerate/<case>/<method>: the degenerate families of tools::degenerate_pairs() (aligned
// boxes, boxes about a shared axis, aligned prisms of 8 to 64 sides, a box with a prism, two
// copies, A (-) A, coplanar faces; integer coordinates, every tie exact) by osm_prepared (the
// shapes in their body frames, identity poses), qhull and bullet_hull; and the rounded-tie
// families of tools::rounded_pairs() (cos/sin prisms, boxes turned by rounded angles: the
// faces' exact normals are not doubles), Degenerate/<case>_rounded.
// Scaling/<n>/<method>: random polytopes of n points on a sphere per operand (seeded), for
// n = 8 ... 512, by osm_prepared (the whole polytope), osm_planes, qhull and cgal_quickhull,
// and n = 2048 by osm_prepared and osm_planes alone (4 million pairwise sums are too slow to
// hull in every report): how the cost grows with
// |A| |B| and with the output. Every row carries `facets` (the sum's F; for cgal_quickhull
// its triangles), so time per output facet reads off the JSON.
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <memory>
#include <stdexcept>

#include "support/bullet_peer.hpp"
#include "support/cgal_peer.hpp"
#include "support/qhull_peer.hpp"
#include "isa_rows.hpp"
#include "support/shapes.hpp"

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

// Two shapes prepared once in their body frames and B's pose: B's points are turned back
// into its body frame, so the posed sum is the sum of the row's polytopes.
struct PreparedShapes {
  ConvexShape A, B;
  Eigen::Isometry3d pose_b = Eigen::Isometry3d::Identity();
};

PreparedShapes prepare_shapes(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b_body,
                              const Eigen::Matrix3d& rotation) {
  PreparedShapes p;
  if (shape_from_points(a, p.A) != Status::Ok || shape_from_points(b_body, p.B) != Status::Ok)
    throw std::runtime_error("minksum_bench: a benchmark shape did not build");
  p.pose_b.linear() = rotation;
  return p;
}

// The size of the overlay's input, E_A + E_B: its work is O(E_A + E_B + F), so on degenerate
// pairs, whose merged output is much smaller than their input, time per output facet alone
// overstates the cost (two aligned boxes: 24 arcs for 6 facets; turned: 24 for 30).
void count_input(benchmark::State& state, const PreparedShapes& p) {
  state.counters["input_edges"] = double(p.A.polytope().edges.size() + p.B.polytope().edges.size());
}

// The timed loop of osm_prepared and osm_planes (Table1 and Scaling): the sum of posed shapes.
void run_prepared(benchmark::State& state, const PreparedShapes& p, SumParts parts = SumParts::Whole) {
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  MinkowskiSum m;
  Status s = Status::Ok;
  for (auto _ : state) {
    s = minkowski_sum(p.A, identity, p.B, p.pose_b, m, parts);
    benchmark::DoNotOptimize(m.planes.data());
  }
  if (s != Status::Ok) state.SkipWithError("the prepared sum failed");
  state.counters["facets"] = m.F;
  state.counters["vertices"] = m.V;
  count_input(state, p);
}

void Table1Prepared(benchmark::State& state, int row, SumParts parts) {
  const auto pair = tools::table1_pairs()[row];
  run_prepared(state, prepare_shapes(pair.a, pair.b_body, pair.rotation), parts);
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

template <class T>
void Table1KernelBatch(benchmark::State& state) {
  constexpr int N = 32;
  auto A = std::make_unique<BoxBatch<T, N>>(), B = std::make_unique<BoxBatch<T, N>>();
  auto out = std::make_unique<BoxBoxSum<T, N>>();
  tools::fill_table1_cubes(*A, *B);
  for (auto _ : state) {
    box_box_sum(*A, *B, *out);
    benchmark::DoNotOptimize(out->loop[29][N - 1]);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * N);  // the report's time per sum
  state.counters["general"] = double(out->general[0]);
}

void Table1Kernel(benchmark::State& state) {
  Box a, b;
  b.rotation = tools::table1_pairs()[0].rotation;  // the unit cube [-1, 1]^3, turned as in table1_pairs
  MinkowskiSum m;
  for (auto _ : state) {
    minkowski_sum(a, b, m);
    benchmark::DoNotOptimize(m.planes.data());
  }
  state.counters["facets"] = m.F;
  state.counters["vertices"] = m.V;
  state.counters["kernel"] = m.method == Method::Kernel;
}

// The pairwise sums a + s b, formed in the timed loop as a hull method's user must.
void pairwise_sums(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b, double s,
                   std::vector<Eigen::Vector3d>& out) {
  out.clear();
  for (const auto& p : a)
    for (const auto& q : b) out.push_back(p + s * q);
}

// A hull peer on the pairwise sums (qhull: merged facets with ordered loops; bullet_hull).
void HullPeer(benchmark::State& state, const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
              double s, bool bullet) {
  std::vector<peers::QhullFacet> facets;
  std::vector<Eigen::Vector3d> sums;
  int count = 0;
  for (auto _ : state) {
    pairwise_sums(a, b, s, sums);
    if (bullet) {
      count = peers::bullet_hull(sums);
    } else {
      peers::qhull_facets(sums, facets);
      count = int(facets.size());
    }
    benchmark::DoNotOptimize(count);
  }
  state.counters["facets"] = count;
}

void DegeneratePrepared(benchmark::State& state, const tools::DegeneratePair& pair) {
  PreparedShapes p = prepare_shapes(pair.a, pair.b, Eigen::Matrix3d::Identity());
  const Eigen::Isometry3d identity = Eigen::Isometry3d::Identity();
  MinkowskiSum m;
  Status s = Status::Ok;
  for (auto _ : state) {
    s = pair.difference ? minkowski_difference(p.A, identity, p.B, identity, m)
                        : minkowski_sum(p.A, identity, p.B, identity, m);
    benchmark::DoNotOptimize(m.planes.data());
  }
  if (s != Status::Ok || m.corrected) state.SkipWithError("the prepared sum failed or needed the corrector");
  state.counters["facets"] = m.F;
  state.counters["vertices"] = m.V;
  count_input(state, p);
}

void Table1Cgal(benchmark::State& state, int row, bool nef) {
  const Prepared p = prepare(row);
  // (The Nef operands are built outside the loop, as minksum's prepared shapes are.)
  std::unique_ptr<peers::CgalNefOperands> operands;
  if (nef) operands = std::make_unique<peers::CgalNefOperands>(p.A.vertices, p.B.vertices);
  int count = 0;
  for (auto _ : state) {
    count = nef ? operands->sum() : peers::cgal_quickhull(p.A.vertices, p.B.vertices);
    benchmark::DoNotOptimize(count);
  }
  state.counters[nef ? "vertices" : "triangles"] = count;
}

// Two random polytopes of n points on the unit sphere (B rotated and seeded differently).
Prepared scaling_pair(int n) {
  Prepared p;
  polytope_from_points(tools::sphere_points(n, 1000 + unsigned(n)), p.A);
  polytope_from_points(tools::rotated(tools::sphere_points(n, 2000 + unsigned(n)), tools::table1_rotation()), p.B);
  return p;
}

// The same pair as shapes: B prepared from its unrotated points, posed by the rotation.
void ScalingPrepared(benchmark::State& state, int n, SumParts parts) {
  run_prepared(state,
               prepare_shapes(tools::sphere_points(n, 1000 + unsigned(n)), tools::sphere_points(n, 2000 + unsigned(n)),
                              tools::table1_rotation()),
               parts);
}

void ScalingCgal(benchmark::State& state, int n) {
  const Prepared p = scaling_pair(n);
  int count = 0;
  for (auto _ : state) {
    count = peers::cgal_quickhull(p.A.vertices, p.B.vertices);
    benchmark::DoNotOptimize(count);
  }
  state.counters["facets"] = count;
}

const int kRegistered = [] {
  for (int n : {8, 12, 16, 24, 32, 48, 64, 128, 256, 512}) {
    const std::string base = "Scaling/" + std::to_string(n) + "/";
    benchmark::RegisterBenchmark((base + "osm_prepared").c_str(), ScalingPrepared, n, SumParts::Whole)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "osm_planes").c_str(), ScalingPrepared, n, SumParts::Planes)
        ->Unit(benchmark::kMicrosecond);
    const Prepared p = scaling_pair(n);
    benchmark::RegisterBenchmark((base + "qhull").c_str(), HullPeer, p.A.vertices, p.B.vertices, 1.0, false)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "cgal_quickhull").c_str(), ScalingCgal, n)->Unit(benchmark::kMicrosecond);
  }
  benchmark::RegisterBenchmark("Scaling/2048/osm_prepared", ScalingPrepared, 2048, SumParts::Whole)
      ->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("Scaling/2048/osm_planes", ScalingPrepared, 2048, SumParts::Planes)
      ->Unit(benchmark::kMicrosecond);
  const auto pairs = tools::table1_pairs();
  for (int row = 0; row < int(pairs.size()); ++row) {
    const std::string base = "Table1/" + pairs[row].name + "/";
    benchmark::RegisterBenchmark((base + "osm_reference").c_str(), Table1Osm, row, Method::Reference)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "osm_fast").c_str(), Table1Osm, row, Method::Fast)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "osm_prepared").c_str(), Table1Prepared, row, SumParts::Whole)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "osm_planes").c_str(), Table1Prepared, row, SumParts::Planes)
        ->Unit(benchmark::kMicrosecond);
    if (pairs[row].name == "cube_rotcube") {
      benchmark::RegisterBenchmark((base + "osm_kernel").c_str(), Table1KernelBatch<double>)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark((base + "osm_kernel_float").c_str(), Table1KernelBatch<float>)
          ->Unit(benchmark::kMicrosecond);
      benchmark::RegisterBenchmark((base + "osm_kernel_single").c_str(), Table1Kernel)->Unit(benchmark::kMicrosecond);
      bench::register_per_isa("box_box_sum_32", "double", Table1KernelBatch<double>);
      bench::register_per_isa("box_box_sum_32", "float", Table1KernelBatch<float>);
      bench::register_per_isa("box_box_sum_single", "double", Table1Kernel);
    }
    const Prepared p = prepare(row);
    benchmark::RegisterBenchmark((base + "qhull").c_str(), HullPeer, p.A.vertices, p.B.vertices, 1.0, false)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "bullet_hull").c_str(), HullPeer, p.A.vertices, p.B.vertices, 1.0, true)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "cgal_quickhull").c_str(), Table1Cgal, row, false)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "cgal_nef").c_str(), Table1Cgal, row, true)->Unit(benchmark::kMillisecond);
  }
  auto degenerate = tools::degenerate_pairs();
  for (auto& pair : tools::rounded_pairs()) degenerate.push_back(std::move(pair));
  for (const auto& pair : degenerate) {
    const std::string base = "Degenerate/" + pair.name + "/";
    const double sign = pair.difference ? -1 : 1;
    benchmark::RegisterBenchmark((base + "osm_prepared").c_str(), DegeneratePrepared, pair)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "qhull").c_str(), HullPeer, pair.a, pair.b, sign, false)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((base + "bullet_hull").c_str(), HullPeer, pair.a, pair.b, sign, true)
        ->Unit(benchmark::kMicrosecond);
  }
  return 0;
}();

}  // namespace

BENCHMARK_MAIN();
