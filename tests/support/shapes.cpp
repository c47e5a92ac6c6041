#include "support/shapes.hpp"

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

// The rotation of the unit quaternion (4, 1, 2, 3)/sqrt(30), times 30: an integer matrix.
Eigen::Matrix3d exact_rotation_times_30() {
  const double w = 4, x = 1, y = 2, z = 3;
  Eigen::Matrix3d M;
  M << w * w + x * x - y * y - z * z, 2 * (x * y - w * z), 2 * (x * z + w * y), 2 * (x * y + w * z),
      w * w - x * x + y * y - z * z, 2 * (y * z - w * x), 2 * (x * z - w * y), 2 * (y * z + w * x),
      w * w - x * x - y * y + z * z;
  return M;
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

std::vector<Eigen::Isometry3d> trajectory(unsigned seed, int ticks, double near, double far, double step) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  const double pi = 3.14159265358979323846, turn = 0.5 * pi / 180;
  // Radius r = mid + amp sin(wr k + pr); direction at longitude wt k + pt, latitude
  // 0.6 sin(wl k + pl). Each term moves at most step / 2 per tick.
  const double mid = (near + far) / 2, amp = (far - near) / 2;
  const double wr = std::min(0.5 * step / std::max(amp, 1e-300), 2 * pi / 2000);
  const double wt = 0.25 * step / far * (0.5 + 0.5 * u(rng)), wl = 0.25 * step / (0.6 * far) * (0.5 + 0.5 * u(rng));
  const double pr = 2 * pi * u(rng), pt = 2 * pi * u(rng), pl = 2 * pi * u(rng);
  const double spin = 2 * pi * (0.2 + u(rng)) / 5000;  // the rotation axis turns slowly too
  Eigen::Matrix3d R = axis_angle(Vector3d(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5), 2 * pi * u(rng));
  std::vector<Eigen::Isometry3d> out(size_t(std::max(ticks, 0)));
  for (int k = 0; k < ticks; ++k) {
    const double r = mid + amp * std::sin(wr * k + pr), lon = wt * k + pt, lat = 0.6 * std::sin(wl * k + pl);
    const Vector3d axis(std::cos(spin * k), std::sin(spin * k), std::sin(0.7 * spin * k + pl));
    R = Eigen::Quaterniond(R * axis_angle(axis, turn * (0.75 + 0.25 * std::sin(3 * spin * k))))
            .normalized()
            .toRotationMatrix();
    out[size_t(k)].setIdentity();
    out[size_t(k)].linear() = R;
    out[size_t(k)].translation() =
        r * Vector3d(std::cos(lon) * std::cos(lat), std::sin(lon) * std::cos(lat), std::sin(lat));
  }
  return out;
}

Eigen::Matrix3d table1_rotation() { return axis_angle(Vector3d(1, 2, 3), 0.7); }

std::vector<Vector3d> rotated(const std::vector<Vector3d>& pts, const Eigen::Matrix3d& R) {
  std::vector<Vector3d> out;
  for (const auto& p : pts) out.push_back(R * p);
  return out;
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
  const Eigen::Matrix3d M = exact_rotation_times_30();
  std::vector<Vector3d> out;
  for (const auto& p : pts) out.push_back(M * p);
  return out;
}

std::vector<Vector3d> scaled(std::vector<Vector3d> pts, double s) {
  for (auto& p : pts) p *= s;
  return pts;
}

std::vector<Table1Pair> table1_pairs() {
  // Each solid's integer points times 30 (B's before the turn: exact_rotated's scale) and a
  // power of two that brings it near unit size; every step is exact.
  const auto cube = scaled(cube_points(), 7.0 / 128), ico = scaled(exact_icosahedron_points(), 1.0 / 2048),
             dod = scaled(exact_dodecahedron_points(), 1.0 / 32768);
  const Eigen::Matrix3d R = exact_rotation_times_30() / 30;
  const auto pair = [&](const char* name, const std::vector<Vector3d>& a, const std::vector<Vector3d>& b) {
    return Table1Pair{name, scaled(a, 30), exact_rotated(b), scaled(b, 30), R};
  };
  return {pair("cube_rotcube", cube, cube), pair("cube_icosa", cube, ico),  pair("icosa_icosa", ico, ico),
          pair("cube_dodeca", cube, dod),   pair("dodeca_dodeca", dod, dod), pair("icosa_dodeca", ico, dod)};
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

namespace {

// An axis-aligned box of integer half extents h.
std::vector<Vector3d> int_box(const Vector3d& h, const Vector3d& c = Vector3d::Zero()) {
  std::vector<Vector3d> p;
  for (const auto& q : cube_points()) p.push_back(c + q.cwiseProduct(h));
  return p;
}

// A prism over the n-gon of radius r (rounded to integers: convex, exactly planar sides), z in
// [-h, h], the polygon scaled by k (an integer: sides parallel to those of k = 1) and turned by
// `phase` of a step.
std::vector<Vector3d> int_prism(int n, double r, double h, int k, double phase) {
  std::vector<Vector3d> p;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * (i + phase) / n;
    const double x = k * std::round(r * std::cos(t)), y = k * std::round(r * std::sin(t));
    p.emplace_back(x, y, -h), p.emplace_back(x, y, h);
  }
  return p;
}

// Integer points in [-r, r]^3.
std::vector<Vector3d> int_points(std::mt19937_64& rng, int n, int r) {
  std::uniform_int_distribution<int> c(-r, r);
  std::vector<Vector3d> p;
  for (int k = 0; k < n; ++k) p.emplace_back(c(rng), c(rng), c(rng));
  return p;
}

}  // namespace

DegeneratePair degenerate_pair(int family, std::mt19937_64& rng) {
  std::uniform_int_distribution<int> small(1, 8), size(10, 40);
  const auto extents = [&] { return Vector3d(small(rng), small(rng), small(rng)); };
  switch (family) {
    case 0:
      return {"aligned_boxes", int_box(extents()), int_box(extents())};
    case 1: {  // B turned about z by (a, b, c), a^2 + b^2 = c^2: both scaled by c, exact
      static const int kTriples[5][3] = {{3, 4, 5}, {5, 12, 13}, {8, 15, 17}, {7, 24, 25}, {20, 21, 29}};
      const int* t = kTriples[rng() % 5];
      const double a = (rng() % 2 ? 1 : -1) * t[0], b = (rng() % 2 ? 1 : -1) * t[1], c = t[2];
      std::vector<Vector3d> B;
      for (const auto& q : int_box(extents())) B.emplace_back(a * q.x() - b * q.y(), b * q.x() + a * q.y(), c * q.z());
      return {"boxes_shared_axis", scaled(int_box(extents()), c), B};
    }
    case 2:
    case 3:
    case 4:
    case 5: {
      const int n = 8 << (family - 2);
      return {"prisms_" + std::to_string(n), int_prism(n, 10000, size(rng), 1, 0),
              int_prism(n, 10000, size(rng), 1 + int(rng() % 3), 0)};
    }
    case 6:
      return {"box_prism", int_box(1000 * extents()), int_prism(16, 10000, size(rng), 1, 0.5)};
    case 7: {
      const auto p = int_points(rng, size(rng), small(rng));
      return {"identical", p, p};
    }
    case 8: {
      const auto p = int_points(rng, size(rng), small(rng));
      return {"mirrored", p, p, true};
    }
    default: {  // B: A's points on or above the plane z = 0, and points below it inside A's box
      const int r = small(rng);
      auto a = int_points(rng, size(rng), r);
      a.push_back(Vector3d(0, 0, -r - 1)), a.push_back(Vector3d(0, 0, r + 1));
      std::vector<Vector3d> b;
      for (const auto& p : a)
        if (p.z() >= 0) b.push_back(p);
      for (const auto& p : int_points(rng, 6, r)) b.push_back(Vector3d(p.x(), p.y(), -std::abs(p.z()) - 1));
      return {"coplanar_faces", a, b};
    }
  }
}

namespace {

// The member of each of `families` families that seed 1 gives.
std::vector<DegeneratePair> first_members(int families, DegeneratePair (*make)(int, std::mt19937_64&)) {
  std::vector<DegeneratePair> out;
  for (int f = 0; f < families; ++f) {
    std::mt19937_64 rng(1);
    out.push_back(make(f, rng));
  }
  return out;
}

}  // namespace

std::vector<DegeneratePair> degenerate_pairs() { return first_members(kDegenerateFamilies, degenerate_pair); }

std::vector<Vector3d> cos_sin_prism(int n, double r, double z0, double z1, double phase) {
  std::vector<Vector3d> p;
  for (int k = 0; k < n; ++k) {
    const double t = 2 * M_PI * k / n + phase;
    p.emplace_back(r * std::cos(t), r * std::sin(t), z0), p.emplace_back(r * std::cos(t), r * std::sin(t), z1);
  }
  return p;
}

std::vector<Vector3d> turned_box(const Vector3d& h, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  std::vector<Vector3d> p;
  for (const auto& q : cube_points()) {
    const Vector3d x = q.cwiseProduct(h);
    p.emplace_back(c * x.x() - s * x.y(), s * x.x() + c * x.y(), x.z());
  }
  return p;
}

DegeneratePair rounded_pair(int family, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> size(0.2, 1.5), angle(0.05, 1.5);
  const auto slab = [&](double h) { return std::pair<double, double>(-h * size(rng), h * size(rng)); };
  const auto [a0, a1] = slab(0.5);
  const auto [b0, b1] = slab(0.3);
  const double r = size(rng);
  switch (family) {
    case 0:
    case 1:
    case 2:
    case 3: {
      const int n = 8 << family;
      return {"prisms_" + std::to_string(n) + "_rounded", cos_sin_prism(n, r, a0, a1),
              cos_sin_prism(n, r / 2, b0, b1)};
    }
    case 4:
      return {"prisms_16_turned_rounded", cos_sin_prism(16, r, a0, a1), cos_sin_prism(16, r / 2, b0, b1, angle(rng))};
    case 5:
      return {"box_turned_rounded", turned_box(Vector3d(size(rng), size(rng), size(rng)), 0),
              turned_box(Vector3d(size(rng), size(rng), size(rng)) / 2, angle(rng))};
    case 6:
      return {"prism_box_rounded", turned_box(Vector3d(size(rng), size(rng), 0.3 * size(rng)), 0),
              cos_sin_prism(16, r / 2, b0, b1, angle(rng))};
    default: {
      const Eigen::Matrix3d R = axis_angle(Vector3d(size(rng), -size(rng), size(rng)), angle(rng));
      std::vector<Vector3d> a = icosahedron_points(), b = a;
      const double k = size(rng);
      for (auto& p : a) p = R * (r * p);
      for (auto& p : b) p = R * (k * r * p);
      return {"icosa_copies_rounded", a, b};
    }
  }
}

std::vector<DegeneratePair> rounded_pairs() { return first_members(kRoundedFamilies, rounded_pair); }

Triangle random_triangle(std::mt19937_64& rng, double spread) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Vector3d c = spread * Vector3d(u(rng), u(rng), u(rng));
  return {c + Vector3d(u(rng), u(rng), u(rng)), c + Vector3d(u(rng), u(rng), u(rng)),
          c + Vector3d(u(rng), u(rng), u(rng))};
}

namespace {

std::vector<Vector3d> corners(const Box& b) {
  std::vector<Vector3d> p;
  for (int k = 0; k < 8; ++k) p.push_back(box_corner(b, k));
  return p;
}

Box box_of(const Vector3d& half, const Eigen::Matrix3d& rotation = Eigen::Matrix3d::Identity()) {
  Box b;
  b.half_extents = half, b.rotation = rotation;
  return b;
}

}  // namespace

std::vector<FacePair> face_pairs() {
  std::vector<FacePair> out;
  const auto boxes = [&](const std::string& name, const Box& a, const Box& b) {
    FacePair p{name, corners(a), corners(b), true, true, a, b};
    out.push_back(p);
  };
  boxes("boxes", box_of(Vector3d(1, 0.8, 0.5)), box_of(Vector3d(0.4, 0.3, 0.25)));
  for (int n : {8, 16, 32, 64})
    out.push_back({"prisms" + std::to_string(n), cos_sin_prism(n, 1, -0.5, 0.5), cos_sin_prism(n, 0.6, -0.3, 0.3)});
  FacePair box_on_prism{"box_on_prism", cos_sin_prism(32, 1, -0.5, 0.5), {}, false, true};
  box_on_prism.box_b = box_of(Vector3d(0.3, 0.2, 0.15)), box_on_prism.b = corners(box_on_prism.box_b);
  out.push_back(box_on_prism);
  // A polytope with a flat bottom: 48 sphere points, those below -0.2 pressed onto that plane.
  FacePair flat{"polytope_on_box", {}, sphere_points(48, 5), true, false};
  for (Vector3d& v : flat.b) v = 0.4 * v, v.z() = std::max(v.z(), -0.2);
  flat.box_a = box_of(Vector3d(1, 1, 0.5)), flat.a = corners(flat.box_a);
  out.push_back(flat);
  boxes("edge_on_face", box_of(Vector3d(1, 1, 0.5)),
        box_of(Vector3d(0.4, 0.3, 0.25), axis_angle(Vector3d::UnitX(), M_PI / 4)));
  return out;
}

Eigen::Isometry3d face_pose(const FacePair& p, int k, int ticks, double gap, bool rocking) {
  const double t = 2 * M_PI * k / ticks;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  if (rocking) R = axis_angle(Vector3d(std::cos(3 * t), std::sin(3 * t), 0), 1e-3 * std::sin(5 * t));
  double top = -HUGE_VAL, bottom = HUGE_VAL;
  for (const Vector3d& v : p.a) top = std::max(top, v.z());
  for (const Vector3d& v : p.b) bottom = std::min(bottom, (R * v).z());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = R;
  pose.translation() = Vector3d(0.25 * std::cos(t), 0.25 * std::sin(t), top - bottom + gap);
  return pose;
}

}  // namespace minksum::tools
