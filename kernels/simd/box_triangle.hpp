// The box-triangle kernels, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"

namespace minksum::detail {

/// Box-triangle sums (26 planes) and the fused overlap test.
template <class T, class Arch>
struct BoxTriangleKernels : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::scaled, L::load3, L::store3, L::unit_or_zero, L::box_support;
  using typename L::S, typename L::B, typename L::V3;

  // Box-triangle overlap by the separating axis test on the 13 axes (box axes, triangle
  // normal, box axes x triangle edges), fused: one flag per pair (Akenine-Moller's test).
  static void box_triangle_overlap(BoxLanes<T> box, const T* tri, int count, int N, CodeOf<T>* hit) {
    const B zero(T(0)), one(T(1));
    for (int k = 0; k < count; k += S::size) {
      V3 u[3], v[3];
      B h[3];
      for (int i = 0; i < 3; ++i) {
        u[i] = load3(box.u + 3 * i * N, N, k), h[i] = S::load(box.h + i * N + k);
        v[i] = load3(tri + 3 * i * N, N, k);
      }
      const V3 c = load3(box.c, N, k);
      // Work relative to the box centre.
      for (auto& p : v) p = V3{p.x - c.x, p.y - c.y, p.z - c.z};
      const V3 e[3] = {{v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z},
                       {v[2].x - v[1].x, v[2].y - v[1].y, v[2].z - v[1].z},
                       {v[0].x - v[2].x, v[0].y - v[2].y, v[0].z - v[2].z}};
      // An axis separates when the triangle's interval [min d, max d] misses the box's [-r, r].
      // Axes of (nearly) parallel directions are skipped: their rounding could fake a gap.
      auto separates = [&](const V3& n, const B& scale2) {
        const B d0 = dot(n, v[0]), d1 = dot(n, v[1]), d2 = dot(n, v[2]);
        const B tmax = S::max(d0, S::max(d1, d2));
        const B tmin = zero - S::max(zero - d0, S::max(zero - d1, zero - d2));
        B r(T(0));
        for (int q = 0; q < 3; ++q) r = S::fma(h[q], S::abs(dot(n, u[q])), r);
        const auto reliable = dot(n, n) > B(kParallelThreshold<T> * kParallelThreshold<T>) * scale2;
        return reliable && ((tmin > r) || (tmax < zero - r));
      };
      const B e2[3] = {dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])};
      auto out = separates(u[0], one) || separates(u[1], one) || separates(u[2], one) ||
                 separates(cross(e[0], e[1]), e2[0] * e2[1]);
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) out = out || separates(cross(u[i], e[j]), e2[j]);
      S::store_code(hit + k, S::select(out, zero, one));
    }
  }

  // Box-triangle: 13 axes, 26 planes (see BoxTrianglePlanes).
  static void box_triangle(BoxLanes<T> box, const T* tri, int count, int N, bool difference, PlaneLanes<T> out) {
    for (int k = 0; k < count; k += S::size) {
      V3 u[3], v[3];
      B h[3];
      for (int i = 0; i < 3; ++i) {
        u[i] = load3(box.u + 3 * i * N, N, k);
        h[i] = S::load(box.h + i * N + k);
        v[i] = load3(tri + 3 * i * N, N, k);
      }
      const V3 c = load3(box.c, N, k);
      const V3 e[3] = {{v[1].x - v[0].x, v[1].y - v[0].y, v[1].z - v[0].z},
                       {v[2].x - v[1].x, v[2].y - v[1].y, v[2].z - v[1].z},
                       {v[0].x - v[2].x, v[0].y - v[2].y, v[0].z - v[2].z}};
      const B e2[3] = {dot(e[0], e[0]), dot(e[1], e[1]), dot(e[2], e[2])};  // squared lengths
      B valid(0), tri_ok(0);
      const V3 nt = unit_or_zero(cross(e[0], e[1]), e2[0] * e2[1], tri_ok, T(1));
#pragma GCC unroll 13
      for (int p = 0; p < 13; ++p) {
        V3 n;
        if (p < 3) {
          n = u[p], valid = valid + B(T(1 << p));
        } else if (p == 3) {
          n = nt, valid = valid + tri_ok * B(T(1 << 3));
        } else {
          const int j = (p - 4) % 3;
          n = unit_or_zero(cross(u[(p - 4) / 3], e[j]), e2[j], valid, T(1 << p));
        }
        B s, code;
        box_support(n, u, h, s, code);
        // Triangle vertex extremes in n; ties go to the lowest index.
        const B d0 = dot(n, v[0]), d1 = dot(n, v[1]), d2 = dot(n, v[2]);
        B hi = d0, ihi(0), lo = d0, ilo(0);
        ihi = S::select(d1 > hi, B(T(1)), ihi), hi = S::max(hi, d1);
        ihi = S::select(d2 > hi, B(T(2)), ihi), hi = S::max(hi, d2);
        ilo = S::select(d1 < lo, B(T(1)), ilo), lo = S::select(d1 < lo, d1, lo);
        ilo = S::select(d2 < lo, B(T(2)), ilo), lo = S::select(d2 < lo, d2, lo);
        // A (+) T: h(n) = box + max d, h(-n) = box' - min d. A (-) T swaps the roles.
        const B plus = difference ? B(T(0)) - lo : hi, minus = difference ? hi : B(T(0)) - lo;
        const B iplus = difference ? ilo : ihi, iminus = difference ? ihi : ilo;
        const B m = dot(n, c);
        // A degenerate triangle's lane is written as zeros (tri_ok is 0 or 1).
        store3(out.n + 3 * p * N, N, k, scaled(n, tri_ok));
        S::store(out.offset + p * N + k, (s + m + plus) * tri_ok);
        S::store(out.offset + (p + 13) * N + k, (s - m + minus) * tri_ok);
        S::store_code(out.code + p * N + k, S::fma(iplus, B(T(8)), code));
        S::store_code(out.code + (p + 13) * N + k, S::fma(iminus, B(T(8)), B(T(7)) - code));
      }
      // A degenerate triangle: only bit 30 (the lane is invalid); 2^30 is exact in float and
      // fits the int32 code.
      valid = S::select(tri_ok > B(T(0)), valid, B(T(1 << 30)));
      S::store_code(out.valid + k, valid);
    }
  }
};

}  // namespace minksum::detail
