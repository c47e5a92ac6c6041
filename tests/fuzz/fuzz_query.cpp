// The proximity queries on boxes and triangles from arbitrary numbers: a clear status, or
// finite answers that agree with each other (distance >= 0, witnesses that realise it). Kinds
// 3 to 5 drive the coherent entry points (box pairs, box-triangle, prepared shapes) along a
// sequence of poses from the input (first byte 128, 129, 130), small steps and jumps, with one cache: the same status and
// verdict as the cold query at every step, and the same distance and depth to rounding.
#include "fuzz_common.hpp"

#include <algorithm>
#include <initializer_list>
#include <limits>

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

// The next motion of a sequence: a small step (the usual case), or a jump to anywhere.
Eigen::Isometry3d motion(fuzz::Bytes& in) {
  const uint8_t mode = in.take<uint8_t>();
  const double scale = mode < 200 ? 1.0 / 256 : 1.0;
  Eigen::Isometry3d m = Eigen::Isometry3d::Identity();
  Eigen::Quaterniond q(1, scale * in.number(), scale * in.number(), scale * in.number());
  m.linear() = q.normalized().toRotationMatrix();  // (a NaN here is what the check must reject)
  m.translation() = scale * Eigen::Vector3d(in.number(), in.number(), in.number());
  return m;
}

// Coherent and cold answers of one step agree: status, verdict, distance and depth, the last
// two to their rounding: the closest points carry eps times the largest coordinate of the
// posed objects (`reach`), which turns the separating direction by eps reach / distance, and
// the supports along it by eps reach^2 / distance (needles 1e5 times longer than their
// distance leave only that).
void same(Status cold_status, const Proximity& cold, Status warm_status, const Proximity& warm, double reach) {
  if (cold_status != warm_status) fuzz::fail("the coherent query's status differs from the cold one");
  if (cold_status != Status::Ok) return;
  fuzz::check(warm);
  if (cold.intersecting != warm.intersecting) {
    std::fprintf(stderr, "cold: intersecting %d distance %.17g depth %.17g; coherent: intersecting %d distance %.17g depth %.17g\n",
                 int(cold.intersecting), cold.distance, cold.penetration_depth, int(warm.intersecting), warm.distance,
                 warm.penetration_depth);
    fuzz::fail("the coherent query's verdict differs from the cold one");
  }
  const double scale = 1 + cold.max_distance + cold.point_a.cwiseAbs().maxCoeff() + cold.point_b.cwiseAbs().maxCoeff();
  const double gap = std::max(cold.distance, cold.penetration_depth);
  const double tol = 1e-9 * scale + 1024 * std::numeric_limits<double>::epsilon() * reach * std::max(1.0, reach / gap);
  if (std::abs(cold.distance - warm.distance) > tol || std::abs(cold.penetration_depth - warm.penetration_depth) > tol) {
    std::fprintf(stderr, "cold: intersecting %d distance %.17g depth %.17g; coherent: distance %.17g depth %.17g\n",
                 int(cold.intersecting), cold.distance, cold.penetration_depth, warm.distance, warm.penetration_depth);
    fuzz::fail("the coherent query's distance or depth differs from the cold one");
  }
}

// Kinds 3-5: up to 12 motions of B, each answered cold and through one cache.
void sequence(fuzz::Bytes& in, int kind) {
  const Box a = box(in), body = box(in);
  const Triangle tri = triangle(in);
  ConvexShape A, B;
  if (kind == 5) {
    std::vector<Eigen::Vector3d> pa, pb;
    const int na = 4 + in.take<uint8_t>() % 12, nb = 4 + in.take<uint8_t>() % 12;
    for (int k = 0; k < na; ++k) pa.emplace_back(in.number(), in.number(), in.number());
    for (int k = 0; k < nb; ++k) pb.emplace_back(in.number(), in.number(), in.number());
    if (shape_from_points(pa, A) != Status::Ok || shape_from_points(pb, B) != Status::Ok) return;
  }
  ProximityCache cache;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const auto largest = [](std::initializer_list<Eigen::Vector3d> v) {
    double m = 0;
    for (const auto& x : v) m = std::max(m, x.cwiseAbs().maxCoeff());
    return m;
  };
  for (int step = 0; step < 12 && in.n > 0; ++step) {
    pose = pose * motion(in);
    Proximity cold, warm;
    Status sc, sw;
    double reach = 0;
    if (kind == 3) {
      Box b = body;
      b.center = pose * body.center, b.rotation = pose.linear() * body.rotation;
      sc = proximity(a, b, cold), sw = proximity(a, b, cache, warm);
      reach = largest({a.center, b.center}) + a.half_extents.cwiseAbs().sum() + b.half_extents.cwiseAbs().sum();
    } else if (kind == 4) {
      const Triangle t{pose * tri.a, pose * tri.b, pose * tri.c};
      sc = proximity(a, t, cold), sw = proximity(a, t, cache, warm);
      reach = largest({a.center, t.a, t.b, t.c}) + a.half_extents.cwiseAbs().sum();
    } else {
      sc = proximity(A, Eigen::Isometry3d::Identity(), B, pose, cold, kWantContact);
      sw = proximity(A, Eigen::Isometry3d::Identity(), B, pose, cache, warm, kWantContact);
      for (const auto& v : A.polytope().vertices) reach = std::max(reach, largest({v}));
      for (const auto& v : B.polytope().vertices) reach = std::max(reach, largest({pose * v}));
    }
    if (!std::isfinite(reach)) reach = 0;
    same(sc, cold, sw, warm, reach);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  const uint8_t first = in.take<uint8_t>();
  if (first >= 128) {  // (below 128: the single queries, as the older corpus files expect)
    sequence(in, 3 + (first - 128) % 3);
    return 0;
  }
  const uint8_t kind = first % 3;
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
