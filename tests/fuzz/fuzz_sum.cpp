// minkowski_sum / minkowski_difference on arbitrary point sets: a clear status, or a valid
// polytope (Euler, finite planes, every pairwise sum inside every plane within the bound); and
// the proximity of the two polytopes: finite and consistent.
#include "fuzz_common.hpp"

using namespace minksum;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const int na = 1 + in.take<uint8_t>() % 24, nb = 1 + in.take<uint8_t>() % 24;
  const uint8_t flags = in.take<uint8_t>();
  std::vector<Eigen::Vector3d> a, b;
  for (int k = 0; k < na; ++k) a.emplace_back(in.number(), in.number(), in.number());
  for (int k = 0; k < nb; ++k) b.emplace_back(in.number(), in.number(), in.number());
  ConvexPolytope A, B;
  if (polytope_from_points(a, A) != Status::Ok || polytope_from_points(b, B) != Status::Ok) return 0;
  Proximity prox;
  if (proximity(A, B, prox) == Status::Ok) fuzz::check(prox);
  const Method method = flags % 3 == 0 ? Method::Fast : flags % 3 == 1 ? Method::Reference : Method::Hull;
  const bool diff = flags & 4;
  MinkowskiSum m;
  const Status s = diff ? minkowski_difference(A, B, m, method) : minkowski_sum(A, B, m, method);
  if (s != Status::Ok) return 0;  // a status is a clear answer (e.g. DegenerateResult)
  if (!m.euler_ok) fuzz::fail("Euler check failed on an Ok result");
  double size_ = 1;
  for (const auto& v : m.vertices) {
    if (!fuzz::finite(v.point)) fuzz::fail("non-finite vertex");
    size_ = std::max(size_, v.point.cwiseAbs().maxCoeff());
  }
  for (const auto& p : m.planes)
    if (!fuzz::finite(p.normal) || !std::isfinite(p.offset)) fuzz::fail("non-finite plane");
  const double sign = diff ? -1 : 1;
  for (const auto& p : A.vertices)
    for (const auto& q : B.vertices)
      for (const auto& pl : m.planes)
        if (pl.normal.dot(p + sign * q) > pl.offset + 1e-9 * size_) fuzz::fail("a pairwise sum is outside a plane");
  return 0;
}
