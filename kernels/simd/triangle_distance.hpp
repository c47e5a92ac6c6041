// The batched triangle-triangle distance, templated on the float type and the ISA (internal; see lanes.hpp).
#pragma once

#include "simd/lanes.hpp"

namespace minksum::detail {

/// The exact triangle-triangle distance, one pair per lane.
template <class T, class Arch>
struct TriangleDistanceKernels : Lanes<T, Arch> {
  using L = Lanes<T, Arch>;
  using L::dot, L::cross, L::load3, L::store3, L::axpy, L::pick3;
  using typename L::S, typename L::B, typename L::V3;

  // Exact triangle-triangle distance, one pair per lane, without branches: the least of the 9
  // edge-edge distances (closest points of segments, Ericson, "Real-Time Collision Detection",
  // 2005, 5.1.9, with its degenerate cases as selects), the 6 vertex-face distances where the
  // vertex projects into the other (non-flat) triangle, and 0 where an edge pierces the other
  // triangle's interior. Coordinates relative to the first corner of s; a lane whose span is
  // outside [kTriLow, kTriHigh] (products of four coordinates, the most any step takes, would
  // leave the float type's range), not finite, or with a sliver gets NaN, for the caller's
  // scalar path.
  static constexpr T kTriLow = std::is_same_v<T, float> ? T(1e-6) : T(1e-60);
  static constexpr T kTriHigh = std::is_same_v<T, float> ? T(1e6) : T(1e60);

  struct Closest {
    B d2;
    V3 p, q;
    void take(const B& e2, const V3& a, const V3& b) {
      const auto better = e2 < d2;
      d2 = S::select(better, e2, d2);
      p = pick3(better, a, p), q = pick3(better, b, q);
    }
  };
  static V3 sub(const V3& a, const V3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  static B clamp01(const B& v) { return S::max(B(T(0)), S::min(B(T(1)), v)); }
  static B safe(const B& v) { return S::select(v == B(T(0)), B(T(1)), v); }

  static void segment_pair(const V3& p0, const V3& p1, const V3& q0, const V3& q1, Closest& best) {
    const B zero(T(0)), one(T(1));
    const V3 d1 = sub(p1, p0), d2 = sub(q1, q0), r = sub(p0, q0);
    const B a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r), c = dot(d1, r), b = dot(d1, d2);
    const V3 x = cross(d1, d2);
    // a e - b^2 and b f - c e by Lagrange's identity, without the cancellation of near-parallel
    // segments (as in the scalar segment_segment).
    const B denom = dot(x, x);
    const B s0 = S::select(denom > zero, clamp01(dot(x, cross(d2, r)) / safe(denom)), zero);
    const B tn = (b * s0 + f) / safe(e);
    const B s_lo = clamp01((zero - c) / safe(a)), s_hi = clamp01((b - c) / safe(a));
    B s = S::select(tn < zero, s_lo, S::select(tn > one, s_hi, s0));
    B t = clamp01(tn);
    s = S::select(e == zero, s_lo, s), t = S::select(e == zero, zero, t);  // q is a point
    s = S::select(a == zero, zero, s);                                     // p is a point
    const V3 cp = axpy(s, d1, p0), cq = axpy(t, d2, q0);
    const V3 gap = sub(cp, cq);
    best.take(dot(gap, gap), cp, cq);
  }

  // Is x inside the triangle v (normal n, not flat)? All three edge tests >= 0.
  static auto inside(const V3 (&v)[3], const V3& n, const V3& x) {
    const B zero(T(0));
    return (dot(cross(sub(v[1], v[0]), sub(x, v[0])), n) >= zero) &&
           (dot(cross(sub(v[2], v[1]), sub(x, v[1])), n) >= zero) &&
           (dot(cross(sub(v[0], v[2]), sub(x, v[2])), n) >= zero);
  }

  // Vertex p against triangle v: the plane distance where p projects inside; and the edges of
  // the other triangle through v: 0 where one pierces v's interior. o is s unless `swap`.
  static void vertex_face(const V3 (&v)[3], const V3& n, const B& n2, const decltype(B(T(0)) < B(T(0)))& solid,
                          const V3 (&o)[3], bool swap, Closest& best) {
    const B zero(T(0)), inf(std::numeric_limits<T>::infinity());
    for (int k = 0; k < 3; ++k) {
      const B h = dot(n, sub(o[k], v[0]));
      const V3 proj = axpy(zero - h / safe(n2), n, o[k]);
      // h (h / n2), not h^2 / n2: h^2 is a product of six coordinates, which leaves the range
      // inside [kTriLow, kTriHigh] (at spans of 1e-60 it read 0 for pairs apart, at 1e52 inf).
      const B e2 = S::select(solid && inside(v, n, proj), h * (h / safe(n2)), inf);
      if (swap)
        best.take(e2, proj, o[k]);
      else
        best.take(e2, o[k], proj);
      // The edge o[k] -> o[k + 1] crossing v's plane strictly inside v.
      const V3& nxt = o[(k + 1) % 3];
      const B hn = dot(n, sub(nxt, v[0]));
      const auto crosses = ((h > zero) && (hn < zero)) || ((h < zero) && (hn > zero));
      const V3 x = axpy(h / safe(h - hn), sub(nxt, o[k]), o[k]);
      best.take(S::select(solid && crosses && inside(v, n, x), zero, inf), x, x);
    }
  }

  // The triangle turned cyclically so that its first corner is opposite its longest edge: the
  // normal is then the cross product of the two shortest edges, the least rounding (as the
  // scalar path's apex_first).
  static void apex_first(V3 (&v)[3]) {
    const V3 e0 = sub(v[1], v[0]), e1 = sub(v[2], v[1]), e2 = sub(v[0], v[2]);
    const B l0 = dot(e0, e0), l1 = dot(e1, e1), l2 = dot(e2, e2);
    const auto k1 = (l2 >= l0) && (l2 > l1), k2 = (l0 > l2) && (l0 > l1);  // else v0 first
    const V3 r0 = pick3(k1, v[1], pick3(k2, v[2], v[0]));
    const V3 r1 = pick3(k1, v[2], pick3(k2, v[0], v[1]));
    const V3 r2 = pick3(k1, v[0], pick3(k2, v[1], v[2]));
    v[0] = r0, v[1] = r1, v[2] = r2;
  }

  static void triangle_distance(const T* s, const T* t, int count, int N, T* dist, T* ps, T* pt) {
    const B zero(T(0)), inf(std::numeric_limits<T>::infinity());
    for (int k = 0; k < count; k += S::size) {
      const V3 o = load3(s, N, k);
      V3 a[3], b[3];
      for (int i = 0; i < 3; ++i) a[i] = sub(load3(s + 3 * i * N, N, k), o), b[i] = sub(load3(t + 3 * i * N, N, k), o);
      apex_first(a), apex_first(b);
      B span = zero;
      for (const V3* v : {&a[1], &a[2], &b[0], &b[1], &b[2]})
        span = S::max(span, S::max(S::abs(v->x), S::max(S::abs(v->y), S::abs(v->z))));
      auto usable = (span == zero) || ((span >= B(kTriLow)) && (span <= B(kTriHigh)));
      Closest best{inf, a[0], b[0]};
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) segment_pair(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3], best);
      // Flat (zero-area) triangles have no face region; their edges cover them (as the scalar
      // path: |n|^2 against 1e-24 of the longest edge's to the fourth).
      // A sliver (solid, but its smallest angle's sine under 1e-4, float 1e-2) goes to the scalar
      // path (NaN): its normal here turns by eps / sin t, which tilts its plane by that much of
      // its length, and a needle's edge tests cannot tell a point just beyond its apex from one
      // inside; the scalar path's normal is accurate and its edge tests exact (closest.cpp).
      const B thin(std::is_same_v<T, float> ? T(1e-4) : T(1e-8));
      const auto normal = [&](const V3(&v)[3], B& n2, decltype(B(T(0)) < B(T(0)))& solid) {
        const V3 e0 = sub(v[1], v[0]), e1 = sub(v[2], v[0]), e2 = sub(v[2], v[1]);
        const V3 n = cross(e0, e1);
        n2 = dot(n, n);
        const B l0 = dot(e0, e0), l1 = dot(e1, e1), longest = S::max(l0, S::max(l1, dot(e2, e2)));
        solid = n2 > B(std::is_same_v<T, float> ? T(1e-12) : T(1e-24)) * longest * longest;
        usable = usable && !(solid && (n2 < thin * longest * S::max(l0, l1)));
        return n;
      };
      B na2, nb2;
      decltype(zero < zero) solid_a, solid_b;
      const V3 na = normal(a, na2, solid_a), nb = normal(b, nb2, solid_b);
      vertex_face(b, nb, nb2, solid_b, a, false, best);  // a's vertices and edges against b
      vertex_face(a, na, na2, solid_a, b, true, best);   // b's against a
      const B nan(std::numeric_limits<T>::quiet_NaN());
      S::store(dist + k, S::select(usable, S::sqrt(best.d2), nan));
      store3(ps, N, k, V3{best.p.x + o.x, best.p.y + o.y, best.p.z + o.z});
      store3(pt, N, k, V3{best.q.x + o.x, best.q.y + o.y, best.q.z + o.z});
    }
  }
};

}  // namespace minksum::detail
