// The batched box-box and box-triangle kernels on arbitrary floats, on every ISA this CPU has:
// no crash or sanitizer report for any input, and for valid boxes (finite, positive extents,
// a rotation) finite planes and proximities, equal across ISAs within float rounding.
#include "fuzz_common.hpp"

#include <memory>

using namespace minksum;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  constexpr int N = kLaneMultiple;
  auto A = std::make_unique<BoxBatch<float, N>>(), B = std::make_unique<BoxBatch<float, N>>();
  auto T = std::make_unique<TriangleBatch<float, N>>();
  bool valid[N];
  const int count = 1 + in.take<uint8_t>() % N;
  for (int k = 0; k < count; ++k) {
    Box b[2];
    for (Box& x : b) {
      x.center = Eigen::Vector3d(in.number(), in.number(), in.number());
      x.half_extents = Eigen::Vector3d(in.number(), in.number(), in.number()).cwiseAbs();
      Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
      x.rotation = q.norm() > 1e-3 && std::isfinite(q.norm()) ? q.normalized().toRotationMatrix() : Eigen::Matrix3d::Identity();
    }
    Triangle t;
    for (Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) *v = Eigen::Vector3d(in.number(), in.number(), in.number());
    // Valid in float: finite, extents well inside float's range.
    valid[k] = true;
    for (const Box& x : b)
      valid[k] = valid[k] && check_box(x) == Status::Ok && x.center.cwiseAbs().maxCoeff() < 1e6 &&
                 x.half_extents.minCoeff() > 1e-3 && x.half_extents.maxCoeff() < 1e6;
    A->set(k, b[0]), B->set(k, b[1]), T->set(k, t);
  }
  A->count = B->count = T->count = count;
  A->pad(), B->pad(), T->pad();
  auto planes = std::make_unique<BoxBoxPlanes<float, N>>();
  auto prox = std::make_unique<BoxBoxProximity<float, N>>(), first = std::make_unique<BoxBoxProximity<float, N>>();
  auto tri = std::make_unique<BoxTrianglePlanes<float, N>>();
  const Isa best = active_isa();
  bool have_first = false;
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!force_isa(isa)) continue;
    box_box_planes(*A, *B, true, *planes);
    box_triangle_planes(*A, *T, false, *tri);
    box_box_proximity(*A, *B, *prox);
    for (int k = 0; k < count; ++k) {
      if (!valid[k]) continue;
      for (int p = 0; p < 30; ++p)
        if (!std::isfinite(planes->offset[p][k])) fuzz::fail("non-finite plane offset for valid boxes");
      if (!std::isfinite(prox->distance[k]) || !std::isfinite(prox->depth[k])) fuzz::fail("non-finite proximity for valid boxes");
      if (have_first) {
        const float scale = 1 + std::abs(first->distance[k]) + std::abs(first->depth[k]) + 4 * float(A->h[0][k] + B->h[0][k] + A->h[1][k] + B->h[1][k] + A->h[2][k] + B->h[2][k]) +
                            std::abs(A->c[0][k]) + std::abs(B->c[0][k]) + std::abs(A->c[1][k]) + std::abs(B->c[1][k]) + std::abs(A->c[2][k]) + std::abs(B->c[2][k]);
        if (std::abs(prox->distance[k] - first->distance[k]) > 1e-3f * scale) fuzz::fail("ISAs disagree on a distance");
      }
    }
    if (!have_first) std::swap(prox, first), have_first = true;
  }
  force_isa(best);
  return 0;
}
