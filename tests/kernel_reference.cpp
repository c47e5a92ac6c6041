#include "kernel_reference.hpp"

#include <limits>

namespace minksum::detail {

using Eigen::Vector3d;

double box_support_brute(const Box& b, const Vector3d& n, int* code) {
  double best = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < 8; ++k)
    if (const double h = n.dot(box_corner(b, k)); h > best) best = h, *code = k;
  return best;
}

namespace {

// Unit axis, or invalid when |c| <= tau * scale (parallel edges).
bool unit_axis(const Vector3d& c, double scale, double tau, Vector3d& n) {
  if (!(c.norm() > tau * scale)) return false;
  n = c.normalized();
  return true;
}

// Fills planes p and p + axes of axis n (zeroed if invalid); `support` sets a plane's offset
// and support pair from its normal.
template <class Support>
void both_sides(KernelPlane* out, int p, int axes, bool valid, const Vector3d& n, Support support) {
  for (int side = 0; side < 2; ++side) {
    KernelPlane& k = out[p + axes * side];
    k = KernelPlane{};
    k.valid = valid;
    if (!valid) continue;
    k.normal = side ? Vector3d(-n) : n;
    support(k);
  }
}

}  // namespace

void box_box_reference(const Box& a, const Box& b, bool difference, double tau, KernelPlane (&out)[30]) {
  const double s = difference ? -1 : 1;
  for (int p = 0; p < 15; ++p) {
    Vector3d n;
    bool valid = true;
    if (p < 3)
      n = a.rotation.col(p);
    else if (p < 6)
      n = b.rotation.col(p - 3);
    else
      valid = unit_axis(a.rotation.col((p - 6) / 3).cross(b.rotation.col((p - 6) % 3)), 1, tau, n);
    both_sides(out, p, 15, valid, n, [&](KernelPlane& k) {
      // h_{A (+) sB}(n) = h_A(n) + h_B(s n); B's support corner is the maximiser in s n.
      k.offset = box_support_brute(a, k.normal, &k.i) + box_support_brute(b, s * k.normal, &k.j);
    });
  }
}

void box_triangle_reference(const Box& box, const Triangle& tri, bool difference, double tau, KernelPlane (&out)[26]) {
  const Vector3d v[3] = {tri.a, tri.b, tri.c};
  const Vector3d e[3] = {v[1] - v[0], v[2] - v[1], v[0] - v[2]};
  Vector3d nt;
  const bool tri_ok = unit_axis(e[0].cross(e[1]), e[0].norm() * e[1].norm(), tau, nt);
  const double s = difference ? -1 : 1;
  for (int p = 0; p < 13; ++p) {
    Vector3d n;
    bool valid = tri_ok;
    if (p < 3)
      n = box.rotation.col(p);
    else if (p == 3)
      n = nt;
    else
      valid = tri_ok && unit_axis(box.rotation.col((p - 4) / 3).cross(e[(p - 4) % 3]), e[(p - 4) % 3].norm(), tau, n);
    both_sides(out, p, 13, valid, n, [&](KernelPlane& k) {
      double best = -std::numeric_limits<double>::infinity();
      for (int i = 0; i < 3; ++i)  // the first vertex of s T that is extreme in n
        if (s * k.normal.dot(v[i]) > best) best = s * k.normal.dot(v[i]), k.j = i;
      k.offset = box_support_brute(box, k.normal, &k.i) + best;
    });
  }
}

}  // namespace minksum::detail
