// Speed against error (issue 7). SpeedError/<set>/<method>/<precision>/<isa> runs every case of
// a set once per iteration; its counters:
//   s_per_case      time per sum
//   max_rel_error   the worst support-function error over the set's cases, relative to the
//                   sum's size: over 10,000 seeded directions u, |h_out(u) - h_A(u) - h_B(u)|
//                   with h_A + h_B in long double (the exact sum's support function to far
//                   below the errors measured); for the kernel, which outputs planes only, at
//                   its valid planes' normals
//   exact_structure the fraction of cases whose V, E, F (the kernel: its distinct valid planes
//                   against F) equal the exact ones; -1 for cgal_quickhull, which outputs
//                   triangles. Exact: CGAL's Epeck hull of the pairwise sums (coplanar
//                   triangles merged) for inputs whose coordinates are exact (the Table 1 pairs
//                   in exact coordinates, aligned boxes, dyadic triangles); for two boxes turned
//                   against each other, the structure of the ideal pair (30 facets, 32 vertices:
//                   the rounded corners of a turned box are not exactly coplanar, so the exact
//                   hull of the doubles splits its faces)
// Sets: "generic" (the Table 1 pairs in exact coordinates and 10 random box pairs), "hard" (../shared/GUIDE.md
// section 3: rotations of 1e-3 ... 1e-15 rad, aligned and 45-degree boxes, offsets of 1e6,
// scale ratios of 1e-6, a 1e-7 thin box, a triangle on a box face, identical solids), "rounded"
// (tools::rounded_pairs(): cos/sin prisms and boxes turned by rounded angles, whose exact
// structure CGAL's Epeck hull of the exact pairwise sums gives). The kernel
// (box-box pairs only) runs in float and double on every ISA this CPU supports.
// NearParallel/<k>/<method>: two unit cubes turned by 10^-k rad about a generic axis, k = 1 ...
// 15: the error, the facet count against the exact one, whether Euler held (euler_ok) and
// whether the corrector ran (corrected).
#include <benchmark/benchmark.h>
#include <minksum/minksum.hpp>

#include <cmath>
#include <map>
#include <memory>
#include <random>

#include "support/cgal_peer.hpp"
#include "support/shapes.hpp"

namespace {

using namespace minksum;
using Eigen::Vector3d;

struct Case {
  std::vector<Vector3d> a, b;
  bool boxes = false;  // a and b are boxes ba, bb (the kernel's input)
  Box ba, bb;
  ConvexPolytope A, B;
  peers::ExactCounts exact;
  double size = 1;  // the sum's largest coordinate
};

std::vector<Vector3d> corners(const Box& b) {
  std::vector<Vector3d> p;
  for (int k = 0; k < 8; ++k) p.push_back(box_corner(b, k));
  return p;
}

// exact: the structure if known (a turned box pair), else CGAL's exact one of the input.
Case make_case(std::vector<Vector3d> a, std::vector<Vector3d> b, const peers::ExactCounts* exact = nullptr) {
  Case c;
  c.a = std::move(a), c.b = std::move(b);
  polytope_from_points(c.a, c.A), polytope_from_points(c.b, c.B);
  c.exact = exact ? *exact : peers::exact_counts(c.a, c.b, 1);
  for (const auto& p : c.a)
    for (const auto& q : c.b) c.size = std::max(c.size, (p + q).cwiseAbs().maxCoeff());
  return c;
}

// Two boxes turned against each other (generic: no two edges parallel): 30 facets (6 + 6
// faces, 9 x 2 edge pairs), 32 vertices, 60 edges; aligned boxes: CGAL's exact structure.
Case box_case(const Box& a, const Box& b, bool turned = true) {
  const peers::ExactCounts generic{32, 60, 30};
  Case c = make_case(corners(a), corners(b), turned ? &generic : nullptr);
  c.boxes = true, c.ba = a, c.bb = b;
  return c;
}

Box box(const Vector3d& h, const Eigen::Matrix3d& R = Eigen::Matrix3d::Identity(),
        const Vector3d& c = Vector3d::Zero()) {
  Box b;
  b.half_extents = h, b.rotation = R, b.center = c;
  return b;
}

const Vector3d kGeneric = Vector3d(0.3, -0.5, 0.81).normalized();

const std::vector<Case>& cases(const std::string& set) {
  static std::map<std::string, std::vector<Case>> all;
  if (all.count(set)) return all[set];
  std::vector<Case>& out = all[set];
  const auto R = tools::table1_rotation();
  if (set == "rounded") {  // (no kernel rows: the boxes here are polytopes of rounded corners)
    for (const auto& pair : tools::rounded_pairs()) out.push_back(make_case(pair.a, pair.b));
  } else if (set == "generic") {
    for (const auto& pair : tools::table1_pairs())
      out.push_back(pair.name == "cube_rotcube" ? box_case(box({1, 1, 1}), box({1, 1, 1}, R))
                                                : make_case(pair.a, pair.b));
    std::mt19937_64 rng(5);
    for (int k = 0; k < 10; ++k) out.push_back(box_case(tools::random_box(rng, 0), tools::random_box(rng, 0)));
  } else {
    for (int e = 3; e <= 15; e += 2)
      out.push_back(box_case(box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle(kGeneric, std::pow(10.0, -e)))));
    out.push_back(box_case(box({1, 2, 3}), box({0.5, 0.25, 4}), false));
    out.push_back(box_case(box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle({0, 0, 1}, M_PI / 4)), false));
    const Vector3d far(1e6, -1e6, 1e6);
    out.push_back(box_case(box({1, 2, 3}, Eigen::Matrix3d::Identity(), far), box({1, 1, 1}, R, far)));
    out.push_back(box_case(box({1, 1, 1}, R), box({1e-6, 1e-6, 1e-6}, tools::axis_angle(kGeneric, 0.3))));
    out.push_back(box_case(box({1, 1, 1e-7}), box({1, 1, 1}, R)));
    out.push_back(make_case(corners(box({1, 1, 1})), {{-0.5, -0.5, 1}, {0.75, -0.25, 1}, {0.125, 0.5, 1}}));
    const auto d = tools::exact_rotated(tools::scaled(tools::exact_dodecahedron_points(), 30));
    out.push_back(make_case(d, d));
  }
  return out;
}

// 10,000 seeded unit directions.
const std::vector<Vector3d>& directions() {
  static const std::vector<Vector3d> dirs = tools::sphere_points(10000, 99);
  return dirs;
}

// |h_out(u) - h_A(u) - h_B(u)| / size, the worst over the directions; h_out from vertices.
double support_error(const Case& c, const std::vector<Vector3d>& vertices) {
  double worst = 0;
  for (const auto& u : directions()) {
    long double ha = -INFINITY, hb = -INFINITY, ho = -INFINITY;
    for (const auto& p : c.a)
      ha = std::max(ha, (long double)u.x() * p.x() + (long double)u.y() * p.y() + (long double)u.z() * p.z());
    for (const auto& p : c.b)
      hb = std::max(hb, (long double)u.x() * p.x() + (long double)u.y() * p.y() + (long double)u.z() * p.z());
    for (const auto& p : vertices)
      ho = std::max(ho, (long double)u.x() * p.x() + (long double)u.y() * p.y() + (long double)u.z() * p.z());
    worst = std::max(worst, double(std::abs(ho - ha - hb)));
  }
  return worst / c.size;
}

void report(benchmark::State& state, size_t n, double error, double exact_fraction) {
  state.counters["s_per_case"] =
      benchmark::Counter(double(n), benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["max_rel_error"] = error;
  state.counters["exact_structure"] = exact_fraction;
}

// A Minkowski sum method on the set, its kernels (the fast path's small-operand edge signs) on
// one ISA.
void Osm(benchmark::State& state, std::string set, Method method, Isa isa) {
  const auto& cs = cases(set);
  std::vector<MinkowskiSum> out(cs.size());
  const Isa before = active_isa();
  force_isa(isa);
  for (auto _ : state)
    for (size_t k = 0; k < cs.size(); ++k) minkowski_sum(cs[k].A, cs[k].B, out[k], method);
  force_isa(before);
  double error = 0, exact = 0;
  for (size_t k = 0; k < cs.size(); ++k) {
    std::vector<Vector3d> v;
    for (const auto& x : out[k].vertices) v.push_back(x.point);
    error = std::max(error, support_error(cs[k], v));
    exact += out[k].V == cs[k].exact.V && out[k].E == cs[k].exact.E && out[k].F == cs[k].exact.F;
  }
  report(state, cs.size(), error, exact / double(cs.size()));
}

void CgalQuickhull(benchmark::State& state, std::string set) {
  const auto& cs = cases(set);
  for (auto _ : state)
    for (const auto& c : cs) benchmark::DoNotOptimize(peers::cgal_quickhull(c.A.vertices, c.B.vertices));
  double error = 0;
  for (const auto& c : cs) {
    std::vector<Vector3d> v;
    peers::cgal_quickhull(c.A.vertices, c.B.vertices, &v);
    error = std::max(error, support_error(c, v));
  }
  report(state, cs.size(), error, -1);
}

// The box-box kernel on the set's box pairs, in one batch, on one ISA.
template <class T>
void Kernel(benchmark::State& state, std::string set, Isa isa) {
  std::vector<const Case*> cs;
  for (const auto& c : cases(set))
    if (c.boxes) cs.push_back(&c);
  auto A = std::make_unique<BoxBatch<T, 64>>(), B = std::make_unique<BoxBatch<T, 64>>();
  auto out = std::make_unique<BoxBoxPlanes<T, 64>>();
  for (size_t k = 0; k < cs.size(); ++k) A->set(int(k), cs[k]->ba), B->set(int(k), cs[k]->bb);
  A->count = B->count = int(cs.size());
  A->pad(), B->pad();
  const Isa before = active_isa();
  force_isa(isa);
  for (auto _ : state) {
    box_box_planes(*A, *B, false, *out);
    benchmark::DoNotOptimize(out->offset[0][0]);
  }
  force_isa(before);
  double error = 0, exact = 0;
  for (size_t k = 0; k < cs.size(); ++k) {
    std::vector<Vector3d> normals;
    for (int p = 0; p < 30; ++p) {
      const int axis = p % 15;
      if (!((long long)out->valid[k] >> axis & 1)) continue;
      Vector3d n(out->n[axis][0][k], out->n[axis][1][k], out->n[axis][2][k]);
      if (p >= 15) n = -n;
      const double len = n.norm();
      long double ha = -INFINITY, hb = -INFINITY;
      for (const auto& q : cs[k]->a)
        ha = std::max(ha, (long double)n.x() * q.x() + (long double)n.y() * q.y() + (long double)n.z() * q.z());
      for (const auto& q : cs[k]->b)
        hb = std::max(hb, (long double)n.x() * q.x() + (long double)n.y() * q.y() + (long double)n.z() * q.z());
      error = std::max(error, double(std::abs((long double)out->offset[p][k] - ha - hb)) / len / cs[k]->size);
      bool seen = false;  // distinct planes only (aligned boxes repeat their faces)
      for (const auto& m : normals) seen = seen || (m - n / len).norm() < 1e-6;
      if (!seen) normals.push_back(n / len);
    }
    exact += int(normals.size()) == cs[k]->exact.F;
  }
  report(state, cs.size(), error, exact / double(cs.size()));
}

void NearParallel(benchmark::State& state, int k, Method method) {
  const Case c = box_case(box({1, 1, 1}), box({1, 1, 1}, tools::axis_angle(kGeneric, std::pow(10.0, -k))));
  MinkowskiSum m;
  for (auto _ : state) minkowski_sum(c.A, c.B, m, method);
  std::vector<Vector3d> v;
  for (const auto& x : m.vertices) v.push_back(x.point);
  state.counters["max_rel_error"] = support_error(c, v);
  state.counters["facets"] = m.F;
  state.counters["exact_facets"] = c.exact.F;
  state.counters["euler_ok"] = m.euler_ok;
  state.counters["corrected"] = m.corrected;
}

const int kRegistered = [] {
  for (const std::string set : {"generic", "hard", "rounded"}) {
    const std::string base = "SpeedError/" + set + "/";
    benchmark::RegisterBenchmark((base + "osm_reference/double/scalar").c_str(), Osm, set, Method::Reference,
                                 Isa::Scalar);
    benchmark::RegisterBenchmark((base + "osm_hull/double/scalar").c_str(), Osm, set, Method::Hull, Isa::Scalar);
    benchmark::RegisterBenchmark((base + "cgal_quickhull/double/scalar").c_str(), CgalQuickhull, set);
    for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
      if (!isa_supported(isa)) continue;
      benchmark::RegisterBenchmark((base + "osm_fast/double/" + to_string(isa)).c_str(), Osm, set, Method::Fast, isa);
      if (set == "rounded") continue;  // (no box pair)
      benchmark::RegisterBenchmark((base + "osm_kernel/float/" + to_string(isa)).c_str(), Kernel<float>, set, isa);
      benchmark::RegisterBenchmark((base + "osm_kernel/double/" + to_string(isa)).c_str(), Kernel<double>, set, isa);
    }
  }
  for (int k = 1; k <= 15; ++k)
    for (auto [name, method] : {std::pair{"osm_fast", Method::Fast}, std::pair{"osm_reference", Method::Reference},
                                std::pair{"osm_hull", Method::Hull}})
      benchmark::RegisterBenchmark(("NearParallel/" + std::to_string(k) + "/" + name).c_str(), NearParallel, k, method)
          ->Unit(benchmark::kMicrosecond);
  return 0;
}();

}  // namespace
