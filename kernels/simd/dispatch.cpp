// ISA dispatch (chosen once at start-up) and the single-pair API.
#include <minksum/kernels.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <xsimd/config/xsimd_cpuid.hpp>

#include "simd/box_pair_data.hpp"
#include "simd/simd.hpp"

namespace minksum {

const char* to_string(Isa isa) {
  switch (isa) {
    case Isa::Scalar:
      return "scalar";
    case Isa::Sse4_2:
      return "sse4_2";
    case Isa::Avx2:
      return "avx2";
    case Isa::Avx512:
      return "avx512";
  }
  return "unknown";
}

bool isa_supported(Isa isa) {
  const auto cpu = xsimd::available_architectures();
  switch (isa) {
    case Isa::Scalar:
      return true;
    case Isa::Sse4_2:
      return cpu.sse4_2;
    case Isa::Avx2:
      return cpu.avx2 && cpu.fma3_avx2;
    case Isa::Avx512:
      return cpu.avx512f && cpu.avx512cd && cpu.avx512dq && cpu.avx512bw;
  }
  return false;
}

namespace {

const detail::KernelTable& table_of(Isa isa) {
  switch (isa) {
    case Isa::Sse4_2:
      return detail::kTableSse4_2;
    case Isa::Avx2:
      return detail::kTableAvx2;
    case Isa::Avx512:
      return detail::kTableAvx512;
    default:
      return detail::kTableScalar;
  }
}

// The active table: constant-initialised to the scalar one, so it is valid even for callers in
// other static initialisers, then switched once at start-up to MINKSUM_ISA if set and
// supported, else to the best ISA this CPU supports. A plain pointer: no guard, no lock.
Isa g_isa = Isa::Scalar;
const detail::KernelTable* g_table = &detail::kTableScalar;
const bool g_selected = [] {
  Isa best = Isa::Scalar;
  for (Isa isa : {Isa::Sse4_2, Isa::Avx2, Isa::Avx512})
    if (isa_supported(isa)) best = isa;
  if (const char* env = std::getenv("MINKSUM_ISA"))
    for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512})
      if (std::strcmp(env, to_string(isa)) == 0 && isa_supported(isa)) best = isa;
  g_isa = best;
  g_table = &table_of(best);
  return true;
}();

const detail::KernelTable& dispatch() { return *g_table; }

}  // namespace

Isa active_isa() { return g_isa; }

bool force_isa(Isa isa) {
  if (!isa_supported(isa)) return false;
  g_isa = isa;
  g_table = &table_of(isa);
  return true;
}

namespace detail {

void box_box(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, bool difference, PlaneLanes<float> out,
             SumLanes<float> sum) {
  dispatch().box_box_f(a, b, count, stride, difference, out, sum);
}
void box_box(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, bool difference, PlaneLanes<double> out,
             SumLanes<double> sum) {
  dispatch().box_box_d(a, b, count, stride, difference, out, sum);
}
void box_triangle(BoxLanes<float> box, const float* tri, int count, int stride, bool difference,
                  PlaneLanes<float> out) {
  dispatch().box_tri_f(box, tri, count, stride, difference, out);
}
void box_triangle(BoxLanes<double> box, const double* tri, int count, int stride, bool difference,
                  PlaneLanes<double> out) {
  dispatch().box_tri_d(box, tri, count, stride, difference, out);
}

void box_box_proximity(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, ProximityLanes<float> out) {
  dispatch().box_box_proximity_f(a, b, count, stride, out);
}
void box_box_proximity(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, ProximityLanes<double> out) {
  dispatch().box_box_proximity_d(a, b, count, stride, out);
}

void box_box_separation(BoxLanes<float> a, BoxLanes<float> b, int count, int stride, float* bound, std::int32_t* hit) {
  dispatch().box_box_separation_f(a, b, count, stride, bound, hit);
}
void box_box_separation(BoxLanes<double> a, BoxLanes<double> b, int count, int stride, double* bound,
                        std::int64_t* hit) {
  dispatch().box_box_separation_d(a, b, count, stride, bound, hit);
}
void box_triangle_overlap(BoxLanes<float> box, const float* tri, int count, int stride, std::int32_t* hit) {
  dispatch().box_triangle_overlap_f(box, tri, count, stride, hit);
}
void box_triangle_overlap(BoxLanes<double> box, const double* tri, int count, int stride, std::int64_t* hit) {
  dispatch().box_triangle_overlap_d(box, tri, count, stride, hit);
}

namespace {

// The batched triangle distance: the active ISA's kernel, then the scalar path (double) for
// the lanes it leaves NaN (a span beyond its range, or non-finite input).
template <class T>
void triangle_lanes(const T* s, const T* t, int count, int stride, T* distance, T* ps, T* pt,
                    void (*kernel)(const T*, const T*, int, int, T*, T*, T*)) {
  kernel(s, t, count, stride, distance, ps, pt);
  for (int k = 0; k < count; ++k) {
    if (!std::isnan(distance[k])) continue;
    Eigen::Vector3d a[3], b[3], pa, pb;
    for (int i = 0; i < 3; ++i)
      for (int d = 0; d < 3; ++d) a[i][d] = s[(3 * i + d) * stride + k], b[i][d] = t[(3 * i + d) * stride + k];
    distance[k] = T(minksum::triangle_distance(a, b, pa, pb));
    for (int d = 0; d < 3; ++d) ps[d * stride + k] = T(pa[d]), pt[d * stride + k] = T(pb[d]);
  }
}

}  // namespace

void triangle_distance(const float* s, const float* t, int count, int stride, float* distance, float* point_s,
                       float* point_t) {
  triangle_lanes(s, t, count, stride, distance, point_s, point_t, dispatch().tri_tri_f);
}
void triangle_distance(const double* s, const double* t, int count, int stride, double* distance, double* point_s,
                       double* point_t) {
  triangle_lanes(s, t, count, stride, distance, point_s, point_t, dispatch().tri_tri_d);
}

namespace {

// One box as a single lane (stride 1) of the kernels' structure of arrays, read in place:
// Eigen's column-major rotation is already the lanes' u layout.
BoxLanes<double> one_lane(const Box& b) { return {b.center.data(), b.rotation.data(), b.half_extents.data()}; }

}  // namespace

void pack_box_pair(const Box& a, const Box& b, double (&in)[30]) {
  for (int d = 0; d < 3; ++d) {
    in[d] = a.center[d], in[3 + d] = b.center[d];
    in[24 + d] = a.half_extents[d], in[27 + d] = b.half_extents[d];
  }
  // Element by element: a block copy (memmove's wide stores) stalls the kernel's loads that
  // follow at once (store forwarding fails).
  for (int e = 0; e < 9; ++e) in[6 + e] = a.rotation.data()[e], in[15 + e] = b.rotation.data()[e];
}

void box_pair_proximity(const Box& a, const Box& b, PairLevel level, unsigned& active, BoxPair<double>& pair,
                        PairAnswer<double>& out) {
  dispatch().box_pair_d(one_lane(a), one_lane(b), level, active, pair, out);
}

bool side_masks(const double* px, const double* py, const double* pz, int n, const double* gx, const double* gy,
                const double* gz, int m, double filter, std::uint64_t* out) {
  return dispatch().side_masks_d(px, py, pz, n, gx, gy, gz, m, filter, out);
}

}  // namespace detail

void support_push(const float* x, const float* y, const float* z, int n, const float* dx, const float* dy,
                  const float* dz, int k, float* max_out, int* arg_out) {
  dispatch().support_f(x, y, z, n, dx, dy, dz, k, max_out, arg_out);
}

void support_push(const double* x, const double* y, const double* z, int n, const double* dx, const double* dy,
                  const double* dz, int k, double* max_out, int* arg_out) {
  dispatch().support_d(x, y, z, n, dx, dy, dz, k, max_out, arg_out);
}

namespace {

// Converts a single-lane box-triangle result: plane p and p + 13 share axis p; each plane has
// its own code; bit 30 of valid marks a degenerate triangle.
void read_triangle_planes(const double* n, const double* offset, const std::int64_t* code, std::int64_t valid,
                          KernelPlane (&out)[26]) {
  for (int p = 0; p < 26; ++p) {
    const int axis = p % 13;
    KernelPlane& k = out[p];
    k.normal = (p < 13 ? 1.0 : -1.0) * Eigen::Vector3d(n[3 * axis], n[3 * axis + 1], n[3 * axis + 2]);
    k.offset = offset[p];
    k.i = int(code[p] & 7);
    k.j = int(code[p] >> 3);
    k.valid = ((valid >> axis) & 1) && !(valid >> 30 & 1);
  }
}

}  // namespace

void box_box_planes(const Box& a, const Box& b, bool difference, BoxBoxPair& out) {
  double in[30];
  detail::pack_box_pair(a, b, in);
  dispatch().box_box_single_d(in, difference, &out.n[0][0], &out.offset[0][0], out.code, out.valid);
}

KernelPlane BoxBoxPair::plane(int p) const {
  const int q = p % 15, side = p < 15 ? 0 : 1;
  const std::int64_t c = side ? 63 - code[q] : code[q];  // both corner codes complemented
  KernelPlane k;
  k.normal = (side ? -1.0 : 1.0) * Eigen::Vector3d(n[0][q], n[1][q], n[2][q]);
  k.offset = offset[side][q];
  k.i = int(c & 7);
  k.j = int(c >> 3);
  k.valid = valid[q] != 0;
  return k;
}

void box_triangle_planes(const Box& box, const Triangle& tri, bool difference, KernelPlane (&out)[26]) {
  double v[9], n[39], offset[26];
  const Eigen::Vector3d* p[3] = {&tri.a, &tri.b, &tri.c};
  for (int i = 0; i < 3; ++i)
    for (int d = 0; d < 3; ++d) v[3 * i + d] = (*p[i])[d];
  std::int64_t code[26], valid;
  detail::kTableScalar.box_tri_d(detail::one_lane(box), v, 1, 1, difference, {n, offset, code, &valid});
  read_triangle_planes(n, offset, code, valid, out);
}

}  // namespace minksum
