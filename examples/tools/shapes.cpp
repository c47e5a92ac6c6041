#include "shapes.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

namespace minksum::tools {

using Eigen::Vector3d;

namespace {
const double kPhi = (1.0 + std::sqrt(5.0)) / 2.0;

// The three cyclic permutations of (x, y, z) for every sign combination.
void add_cyclic(std::vector<Vector3d>& out, double x, double y, double z) {
  for (int s = 0; s < 8; ++s) {
    const Vector3d p((s & 1) ? -x : x, (s & 2) ? -y : y, (s & 4) ? -z : z);
    for (int r = 0; r < 3; ++r) {
      const Vector3d q(p[r], p[(r + 1) % 3], p[(r + 2) % 3]);
      if (std::find(out.begin(), out.end(), q) == out.end()) out.push_back(q);
    }
  }
}
}  // namespace

std::vector<Vector3d> cube_points() {
  std::vector<Vector3d> p;
  for (int k = 0; k < 8; ++k) p.emplace_back((k & 1) ? 1 : -1, (k & 2) ? 1 : -1, (k & 4) ? 1 : -1);
  return p;
}

std::vector<Vector3d> icosahedron_points() {
  std::vector<Vector3d> p;
  add_cyclic(p, 0, 1, kPhi);
  return p;
}

std::vector<Vector3d> dodecahedron_points() {
  std::vector<Vector3d> p = cube_points();
  add_cyclic(p, 0, 1 / kPhi, kPhi);
  return p;
}

Eigen::Matrix3d axis_angle(const Vector3d& axis, double angle) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

Eigen::Matrix3d table1_rotation() { return axis_angle(Vector3d(1, 2, 3), 0.7); }

std::vector<Vector3d> rotated(const std::vector<Vector3d>& pts, const Eigen::Matrix3d& R) {
  std::vector<Vector3d> out;
  for (const auto& p : pts) out.push_back(R * p);
  return out;
}

std::vector<Table1Pair> table1_pairs() {
  const auto R = table1_rotation();
  const auto cube = cube_points(), ico = icosahedron_points(), dod = dodecahedron_points();
  return {{"cube_rotcube", cube, rotated(cube, R)},   {"cube_icosa", cube, rotated(ico, R)},
          {"icosa_icosa", ico, rotated(ico, R)},      {"cube_dodeca", cube, rotated(dod, R)},
          {"dodeca_dodeca", dod, rotated(dod, R)},    {"icosa_dodeca", ico, rotated(dod, R)}};
}

std::vector<Vector3d> exact_icosahedron_points() {
  std::vector<Vector3d> p;
  for (int s = 0; s < 4; ++s) {
    const double a = (s & 1) ? -55 : 55, b = (s & 2) ? -89 : 89;
    p.insert(p.end(), {{0, a, b}, {a, b, 0}, {b, 0, a}});
  }
  return p;
}

std::vector<Vector3d> exact_dodecahedron_points() {
  std::vector<Vector3d> p = scaled(cube_points(), 1156);
  for (int s = 0; s < 4; ++s) {
    const double a = (s & 1) ? -1870 : 1870, b = (s & 2) ? -715 : 715;
    p.insert(p.end(), {{0, a, b}, {a, b, 0}, {b, 0, a}});
  }
  return p;
}

std::vector<Vector3d> exact_rotated(const std::vector<Vector3d>& pts) {
  const double w = 4, x = 1, y = 2, z = 3;
  Eigen::Matrix3d M;
  M << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y),
      2 * (x * y + w * z), w * w - x * x + y * y - z * z, 2 * (y * z - w * x),
      2 * (x * z - w * y), 2 * (y * z + w * x), w * w - x * x - y * y + z * z;
  std::vector<Vector3d> out;
  for (const auto& p : pts) out.push_back(M * p);
  return out;
}

std::vector<Vector3d> scaled(std::vector<Vector3d> pts, double s) {
  for (auto& p : pts) p *= s;
  return pts;
}

std::vector<Table1Pair> exact_table1_pairs() {
  const auto cube = scaled(cube_points(), 30 * 7), ico = scaled(exact_icosahedron_points(), 30);
  const auto dod = scaled(exact_dodecahedron_points(), 30);
  return {{"cube_rotcube", cube, exact_rotated(cube)},   {"cube_icosa", cube, exact_rotated(ico)},
          {"icosa_icosa", ico, exact_rotated(ico)},      {"cube_dodeca", cube, exact_rotated(dod)},
          {"dodeca_dodeca", dod, exact_rotated(dod)},    {"icosa_dodeca", ico, exact_rotated(dod)}};
}

std::vector<Vector3d> sphere_points(int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g;
  std::vector<Vector3d> out;
  while (int(out.size()) < n) {
    const Vector3d p(g(rng), g(rng), g(rng));
    if (p.norm() > 1e-6) out.push_back(p.normalized());
  }
  return out;
}

Box random_box(std::mt19937_64& rng, double spread, double max_half) {
  std::uniform_real_distribution<double> u(-1, 1), h(0.05, max_half);
  Box b;
  b.center = spread * Vector3d(u(rng), u(rng), u(rng));
  b.rotation = axis_angle(Vector3d(u(rng), u(rng), u(rng)), 3.2 * u(rng));
  b.half_extents = Vector3d(h(rng), h(rng), h(rng));
  return b;
}

Triangle random_triangle(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Vector3d c = spread * Vector3d(u(rng), u(rng), u(rng));
  return {c + Vector3d(u(rng), u(rng), u(rng)), c + Vector3d(u(rng), u(rng), u(rng)),
          c + Vector3d(u(rng), u(rng), u(rng))};
}

}  // namespace minksum::tools
