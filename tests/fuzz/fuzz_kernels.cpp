// The batched box-box, box-triangle and triangle-triangle kernels on arbitrary floats, on every
// ISA this CPU has: no crash or sanitizer report for any input; for valid boxes (finite,
// positive extents, a rotation) the planes of box-box and box-triangle against their scalar
// reference twins (the same valid axes, each offset the exact support at the plane's own normal
// within 8 float ulps of the operands' size, as the README states), finite proximities equal to the exact
// double query, the whole sum's loops on their planes and its planes supporting it,
// minkowski_sum(Box, Box) a closed polytope of support planes, and for finite triangles the
// double triangle distance equal to the scalar path.
#include <minksum/mesh.hpp>

#include "fuzz_common.hpp"
#include "kernel_reference.hpp"

#include <algorithm>
#include <limits>
#include <memory>

using namespace minksum;

namespace {

constexpr double kFloatEps = std::numeric_limits<float>::epsilon();
constexpr double kTau = kParallelThreshold<float>;

// What the float kernels see: every number rounded to float.
Box rounded(const Box& b) {
  Box r;
  r.center = b.center.cast<float>().cast<double>();
  r.half_extents = b.half_extents.cast<float>().cast<double>();
  r.rotation = b.rotation.cast<float>().cast<double>();
  return r;
}
Triangle rounded(const Triangle& t) {
  return {t.a.cast<float>().cast<double>(), t.b.cast<float>().cast<double>(), t.c.cast<float>().cast<double>()};
}

// The size an offset's rounding scales with: the stored normal is within a few ulps of the
// kernel's own (a cross product taken in A's frame and turned back), which moves the support by
// that angle times the operand's reach, not by the terms along the normal (a box 512 long
// moved a plane through its end by 1.2e-5 whose terms were 2).
double size(const Box& b) { return b.center.lpNorm<1>() + b.half_extents.sum(); }

// One kernel plane against its reference twin: the same validity (bar an axis whose cross
// length is within 1 % of the threshold, or `either`, where either is right), and a valid
// plane's offset the exact support `top` at its own normal within 8 ulps of `scale` (the
// operands' size).
void twin(const char* what, int p, bool valid, const KernelPlane& ref, double cross_len, bool either, double offset,
          double top, double scale) {
  if (!either && std::abs(cross_len - kTau) >= 0.01 * kTau && valid != ref.valid) {
    std::fprintf(stderr, "%s plane %d: valid %d, reference %d (cross length %.9g)\n", what, p, int(valid),
                 int(ref.valid), cross_len);
    fuzz::fail("a kernel plane's validity differs from its reference twin");
  }
  if (valid && !(std::abs(offset - top) <= 8 * kFloatEps * scale)) {
    std::fprintf(stderr, "%s plane %d (isa %s): offset %.9g, support %.17g (scale %.9g, cross length %.3g)\n", what, p,
                 to_string(active_isa()), offset, top, scale, cross_len);
    fuzz::fail("a kernel plane's offset is not the support at its normal");
  }
}

// Lane k of box_box_planes(A, B, difference) against box_box_reference.
template <int N>
void check_box_box(const BoxBoxPlanes<float, N>& out, int k, const Box& box_a, const Box& box_b, bool difference) {
  const Box a = rounded(box_a), b = rounded(box_b);
  KernelPlane ref[30];
  detail::box_box_reference(a, b, difference, kTau, ref);
  const double s = difference ? -1 : 1;
  for (int p = 0; p < 30; ++p) {
    const int axis = p % 15;
    const Eigen::Vector3d n =
        (p < 15 ? 1.0 : -1.0) * Eigen::Vector3d(out.n[axis][0][k], out.n[axis][1][k], out.n[axis][2][k]);
    const double cross_len = axis < 6 ? 1 : a.rotation.col((axis - 6) / 3).cross(b.rotation.col((axis - 6) % 3)).norm();
    int code;
    const double top = detail::box_support_brute(a, n, &code) + detail::box_support_brute(b, s * n, &code);
    const double scale = size(a) + size(b);
    twin("box-box", p, out.valid[k] >> axis & 1, ref[p], cross_len, false, out.offset[p][k], top, scale);
  }
}

// Lane k of box_triangle_planes(A, T, difference) against box_triangle_reference.
template <int N>
void check_box_triangle(const BoxTrianglePlanes<float, N>& out, int k, const Box& box, const Triangle& tri,
                        bool difference) {
  const Box a = rounded(box);
  const Triangle t = rounded(tri);
  KernelPlane ref[26];
  detail::box_triangle_reference(a, t, difference, kTau, ref);
  const Eigen::Vector3d v[3] = {t.a, t.b, t.c}, e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  const double tri_len = e[0].cross(e[1]).norm() / (e[0].norm() * e[1].norm());
  const bool degenerate = out.valid[k] >> 30 & 1;
  // The kernel tests each axis in float, its squared cross length against tau^2 times squared
  // edge lengths, and no squared cross length under float's smallest normal number holds a
  // direction (kernels.hpp). Where tau^2 times the squared lengths is under that, the reference
  // in double may still find an axis the kernel drops (a corner 4e-34 off the edge of a 0.05
  // triangle; an edge 2.2e-23 long beside edges of 237): either is right, as a dropped axis
  // leaves the planes conservative. The kernel's valid planes are still checked.
  const double e2[3] = {e[0].squaredNorm(), e[1].squaredNorm(), e[2].squaredNorm()};
  const auto underflows = [](double scale2) { return kTau * kTau * scale2 < std::numeric_limits<float>::min(); };
  const bool lane_either = underflows(e2[0] * e2[1]) || underflows(std::min({e2[0], e2[1], e2[2]}));
  const double s = difference ? -1 : 1;
  for (int p = 0; p < 26; ++p) {
    const int axis = p % 13;
    const Eigen::Vector3d n =
        (p < 13 ? 1.0 : -1.0) * Eigen::Vector3d(out.n[axis][0][k], out.n[axis][1][k], out.n[axis][2][k]);
    double cross_len = axis < 3 ? 1 : tri_len;
    if (axis >= 4) {
      const Eigen::Vector3d& edge = e[(axis - 4) % 3];
      cross_len = std::min(tri_len, a.rotation.col((axis - 4) / 3).cross(edge).norm() / edge.norm());
    }
    int code;
    double top = detail::box_support_brute(a, n, &code) + std::max({s * n.dot(v[0]), s * n.dot(v[1]), s * n.dot(v[2])});
    const double scale = size(a) + std::max({v[0].lpNorm<1>(), v[1].lpNorm<1>(), v[2].lpNorm<1>()});
    twin("box-triangle", p, !degenerate && (out.valid[k] >> axis & 1), ref[p], cross_len, lane_either, out.offset[p][k],
         top, scale);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::Bytes in{data, size};
  constexpr int N = kLaneMultiple;
  auto A = std::make_unique<BoxBatch<float, N>>(), B = std::make_unique<BoxBatch<float, N>>();
  auto T = std::make_unique<TriangleBatch<float, N>>();
  auto S2 = std::make_unique<TriangleBatch<double, N>>(), T2 = std::make_unique<TriangleBatch<double, N>>();
  Triangle tris[N][2];
  Box boxes[N][2];
  bool valid[N], tri_valid[N];
  const int count = 1 + in.take<uint8_t>() % N;
  for (int k = 0; k < count; ++k) {
    Box b[2];
    for (Box& x : b) {
      x.center = Eigen::Vector3d(in.number(), in.number(), in.number());
      x.half_extents = Eigen::Vector3d(in.number(), in.number(), in.number()).cwiseAbs();
      Eigen::Quaterniond q(in.number(), in.number(), in.number(), in.number());
      x.rotation =
          q.norm() > 1e-3 && std::isfinite(q.norm()) ? q.normalized().toRotationMatrix() : Eigen::Matrix3d::Identity();
    }
    Triangle t;
    for (Eigen::Vector3d* v : {&t.a, &t.b, &t.c}) *v = Eigen::Vector3d(in.number(), in.number(), in.number());
    // Valid in float: finite, extents well inside float's range.
    valid[k] = true;
    for (const Box& x : b)
      valid[k] = valid[k] && check_box(x) == Status::Ok && x.center.cwiseAbs().maxCoeff() < 1e6 &&
                 x.half_extents.minCoeff() > 1e-3 && x.half_extents.maxCoeff() < 1e6;
    tri_valid[k] = valid[k] && t.a.cwiseAbs().maxCoeff() < 1e6 && t.b.cwiseAbs().maxCoeff() < 1e6 &&
                   t.c.cwiseAbs().maxCoeff() < 1e6;
    A->set(k, b[0]), B->set(k, b[1]), T->set(k, t);
    boxes[k][0] = b[0], boxes[k][1] = b[1];
    // A second triangle, from the next numbers (or the box's corners when they run out).
    Triangle u{b[0].center, b[1].center, Eigen::Vector3d(in.number(), in.number(), in.number())};
    tris[k][0] = t, tris[k][1] = u;
    S2->set(k, t), T2->set(k, u);
  }
  A->count = B->count = T->count = S2->count = T2->count = count;
  A->pad(), B->pad(), T->pad(), S2->pad(), T2->pad();
  auto dist = std::make_unique<TriangleDistances<double, N>>();
  auto planes = std::make_unique<BoxBoxPlanes<float, N>>();
  auto prox = std::make_unique<BoxBoxProximity<float, N>>(), first = std::make_unique<BoxBoxProximity<float, N>>();
  auto tri = std::make_unique<BoxTrianglePlanes<float, N>>();
  auto whole = std::make_unique<BoxBoxSum<float, N>>();
  const Isa best = active_isa();
  bool have_first = false;
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!force_isa(isa)) {
      static bool told[4] = {};  // (once a run, not once an input)
      if (!told[int(isa)]) std::fprintf(stderr, "fuzz_kernels: NOT TESTED: this CPU lacks %s\n", to_string(isa));
      told[int(isa)] = true;
      continue;
    }
    box_box_planes(*A, *B, true, *planes);
    box_triangle_planes(*A, *T, false, *tri);
    box_box_proximity(*A, *B, *prox);
    box_box_sum(*A, *B, *whole);
    triangle_distance(*S2, *T2, *dist);
    bool summed = false;
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector3d s3[3] = {tris[k][0].a, tris[k][0].b, tris[k][0].c},
                            t3[3] = {tris[k][1].a, tris[k][1].b, tris[k][1].c};
      double span = 0;
      bool finite = true;
      for (const auto* x : {&s3[1], &s3[2], &t3[0], &t3[1], &t3[2]}) {
        span = std::max(span, (*x - s3[0]).cwiseAbs().maxCoeff());
        finite = finite && fuzz::finite(*x);
      }
      if (finite && fuzz::finite(s3[0]) && std::isfinite(span)) {
        Eigen::Vector3d pa, pb;
        const double want = triangle_distance(s3, t3, pa, pb);
        if (!(std::abs(dist->distance[k] - want) <= 1e-9 * span + 1e-300)) {
          std::fprintf(stderr, "isa %s lane %d: %.17g vs %.17g (span %g)\n", to_string(isa), k, dist->distance[k], want,
                       span);
          for (const auto* x : {&s3[0], &s3[1], &s3[2], &t3[0], &t3[1], &t3[2]})
            std::fprintf(stderr, "  %.17g %.17g %.17g\n", x->x(), x->y(), x->z());
          fuzz::fail("the batched triangle distance differs from the scalar path");
        }
      }
      if (!valid[k]) continue;
      for (int p = 0; p < 30; ++p)
        if (!std::isfinite(planes->offset[p][k])) fuzz::fail("non-finite plane offset for valid boxes");
      check_box_box(*planes, k, boxes[k][0], boxes[k][1], true);
      if (tri_valid[k]) check_box_triangle(*tri, k, boxes[k][0], tris[k][0], false);
      if (!std::isfinite(prox->distance[k]) || !std::isfinite(prox->depth[k]))
        fuzz::fail("non-finite proximity for valid boxes");
      const float scale = 1 + 4 * float(A->h[0][k] + B->h[0][k] + A->h[1][k] + B->h[1][k] + A->h[2][k] + B->h[2][k]) +
                          std::abs(A->c[0][k]) + std::abs(B->c[0][k]) + std::abs(A->c[1][k]) + std::abs(B->c[1][k]) +
                          std::abs(A->c[2][k]) + std::abs(B->c[2][k]);
      // The kernels' stated error (kernels.hpp): the sliver facets they skip move the distance by
      // at most kSliverThreshold of the longer half edge; the rest is float rounding, of the
      // inputs (each box rounded to float) and of the arithmetic: 128 float ulps of `scale`.
      const double longest = std::max(boxes[k][0].half_extents.maxCoeff(), boxes[k][1].half_extents.maxCoeff());
      const double bound = kSliverThreshold<float> * longest + 128 * kFloatEps * scale;
      if (have_first && std::abs(prox->distance[k] - first->distance[k]) > 2 * bound)
        fuzz::fail("ISAs disagree on a distance");
      // The batched answer (one facet with a certificate, or all 15) against the exact
      // single-pair query in double (separating axis test and an active-set walk).
      Proximity exact;
      if (proximity(boxes[k][0], boxes[k][1], exact) != Status::Ok)
        fuzz::fail("the exact query rejects a valid box pair");
      if (std::abs(prox->distance[k] - exact.distance) > bound ||
          std::abs(prox->depth[k] - exact.penetration_depth) > bound) {
        std::fprintf(stderr, "isa %s lane %d: distance %.9g vs %.17g, depth %.9g vs %.17g (scale %g, bound %g)\n",
                     to_string(isa), k, prox->distance[k], exact.distance, prox->depth[k], exact.penetration_depth,
                     scale, bound);
        for (const Box& x : boxes[k])
          std::fprintf(stderr,
                       "  box c %.17g %.17g %.17g h %.17g %.17g %.17g\n  R %.17g %.17g %.17g %.17g %.17g %.17g %.17g "
                       "%.17g %.17g\n",
                       x.center.x(), x.center.y(), x.center.z(), x.half_extents.x(), x.half_extents.y(),
                       x.half_extents.z(), x.rotation(0, 0), x.rotation(0, 1), x.rotation(0, 2), x.rotation(1, 0),
                       x.rotation(1, 1), x.rotation(1, 2), x.rotation(2, 0), x.rotation(2, 1), x.rotation(2, 2));
        fuzz::fail("the batched proximity differs from the exact query");
      }
      // The first valid pair through minkowski_sum(Box, Box) (the double kernel on one lane, or
      // the general path; one pair per input and ISA keeps the run short): a closed polytope
      // whose every plane is the support plane of the corner sums.
      if (!summed) {
        summed = true;
        MinkowskiSum sum;
        if (minkowski_sum(boxes[k][0], boxes[k][1], sum) != Status::Ok || !sum.euler_ok || sum.V - sum.E + sum.F != 2)
          fuzz::fail("minkowski_sum(Box, Box) fails on valid boxes");
        Eigen::Vector3d corners[64];
        for (int i = 0; i < 8; ++i)
          for (int j = 0; j < 8; ++j) corners[8 * i + j] = box_corner(boxes[k][0], i) + box_corner(boxes[k][1], j);
        for (const SumPlane& plane : sum.planes) {
          double top = -std::numeric_limits<double>::infinity();
          for (const auto& x : corners) top = std::max(top, plane.normal.dot(x));
          if (std::abs(top - plane.offset) > 1e-12 * double(scale))
            fuzz::fail("minkowski_sum(Box, Box): a plane off the support");
        }
      }
      // The whole sum: every loop vertex on its facet's plane, every pairwise corner sum inside
      // every plane.
      if (!whole->general[k]) continue;
      for (int p = 0; p < 30; ++p) {
        const int q = p % 15;
        const float sgn = p < 15 ? 1.f : -1.f;
        const auto along = [&](int i, int j) {
          float v = 0;
          for (int d = 0; d < 3; ++d)
            v += sgn * whole->planes.n[q][d][k] * (whole->corner_a[i][d][k] + whole->corner_b[j][d][k]);
          return v;
        };
        for (int m = 0; m < 4; ++m) {
          const int v = int(whole->loop[p][k] >> (6 * m) & 63);
          if (std::abs(along(v & 7, v >> 3) - whole->planes.offset[p][k]) > 1e-4f * scale)
            fuzz::fail("a sum vertex off its facet's plane");
        }
        for (int i = 0; i < 8; ++i)
          for (int j = 0; j < 8; ++j)
            if (along(i, j) > whole->planes.offset[p][k] + 1e-4f * scale) fuzz::fail("a facet plane cuts the sum");
      }
    }
    if (!have_first) std::swap(prox, first), have_first = true;
  }
  force_isa(best);
  return 0;
}
