// The proximity queries on boxes and triangles from arbitrary numbers: a clear status, or
// finite answers that agree with each other (distance >= 0, witnesses that realise it).
#include "fuzz_common.hpp"

using namespace minksum;

namespace {

Box box(fuzz::Bytes& in) {
  Box b;
  b.center = Eigen::Vector3d(in.number(), in.number(), in.number());
  b.half_extents = Eigen::Vector3d(in.number(), in.number(), in.number());
  Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
  if (q.norm() > 0 && std::isfinite(q.norm())) b.rotation = q.normalized().toRotationMatrix();
  else b.rotation = Eigen::Matrix3d::Constant(in.number());  // invalid on purpose
  return b;
}

Triangle triangle(fuzz::Bytes& in) {
  Triangle t;
  for (Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) *v = Eigen::Vector3d(in.number(), in.number(), in.number());
  return t;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const uint8_t kind = in.take<uint8_t>() % 3;
  Proximity p;
  Status s;
  if (kind == 0) {
    const Box a = box(in), b = box(in);
    s = proximity(a, b, p);
  } else if (kind == 1) {
    const Box a = box(in);
    s = proximity(a, triangle(in), p);
  } else {
    const Triangle a = triangle(in);
    s = proximity(a, triangle(in), p);
  }
  if (s == Status::Ok) fuzz::check(p);
  return 0;
}
