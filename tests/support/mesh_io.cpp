// Mesh input through the library's readers (minksum/io.hpp); libcgal-demo's meshes are read
// from one member of its .tar.gz with zlib.
#include <minksum/kernels.hpp>
#include "support/mesh_io.hpp"

#include <minksum/io.hpp>

#include <Eigen/Geometry>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

namespace minksum::tools {

bool read_mesh(const std::string& path, Mesh& mesh, std::string& error, bool cloud_ok) {
  return minksum::read_mesh(path, mesh.vertices, mesh.triangles, error, cloud_ok);
}

namespace {

// One member of a gzip-compressed tar archive (ustar: 512-byte headers, size in octal).
bool tar_member(const std::string& archive, const std::string& member, std::string& out) {
  gzFile f = gzopen(archive.c_str(), "rb");
  if (!f) return false;
  char header[512];
  bool found = false;
  while (gzread(f, header, 512) == 512 && header[0] != 0) {
    const std::string name(header, strnlen(header, 100));
    const size_t size = std::strtoull(std::string(header + 124, 12).c_str(), nullptr, 8);
    const size_t padded = (size + 511) / 512 * 512;
    if (name == member) {
      out.resize(padded);
      found = gzread(f, out.data(), unsigned(padded)) == int(padded);
      out.resize(size);
      break;
    }
    if (gzseek(f, z_off_t(padded), SEEK_CUR) < 0) break;
  }
  gzclose(f);
  return found;
}

// (libcgal-demo installs it there; its own doc directory is a link to that one.)
constexpr const char* kDemoArchive = "/usr/share/doc/libcgal-dev/data.tar.gz";

// data/meshes/<name> of libcgal-demo's archive, as it is.
bool read_demo_archive(const std::string& name, Mesh& mesh) {
  std::string text, error;
  std::istringstream stream;
  const std::string ext = std::filesystem::path(name).extension().string();
  mesh = Mesh{};
  return tar_member(kDemoArchive, "data/meshes/" + name, text) && (stream.str(text), true) && !ext.empty() &&
         read_polygons(stream, kDemoArchive, ext.substr(1), mesh.vertices, &mesh.triangles, error) &&
         !mesh.triangles.empty();
}

}  // namespace

bool cgal_demo_points(const std::string& name, std::vector<Eigen::Vector3d>& points) {
  Mesh mesh;
  if (!read_demo_archive(name, mesh)) return false;
  points = std::move(mesh.vertices);
  return true;
}

std::vector<std::string> cad_parts() {
  return {"anchor.off", "blade.off",  "couplingdown.off", "fandisk.off", "joint.off",
          "part.off",   "pinion.off", "rotor.off",        "spool.off",   "turbine.off"};
}

bool cgal_demo_mesh(const std::string& name, Mesh& mesh) {
  if (!read_demo_archive(name, mesh)) return false;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& t : mesh.triangles)
    for (int k : t) lo = lo.cwiseMin(mesh.vertices[size_t(k)]), hi = hi.cwiseMax(mesh.vertices[size_t(k)]);
  const Eigen::Vector3d center = (lo + hi) / 2;
  const double scale = 1 / (hi - lo).norm();
  for (auto& v : mesh.vertices) v = (v - center) * scale;
  return true;
}

namespace {

// The banded poses of B against A (see banded_poses): distance(p) is their distance with B at
// p; B starts at base(rng, rotation) and moves up to `reach` along the direction (beyond it,
// they are apart).
template <class Distance, class Base>
std::vector<Eigen::Isometry3d> banded(Distance distance_at, Base base_at, double reach, double size, unsigned seed,
                                      int count) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1, 1), unit(0, 1);
  std::vector<Eigen::Isometry3d> poses;
  while (int(poses.size()) < count) {
    const int band = band_of(int(poses.size()), count);
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.linear() = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized().toRotationMatrix();
    const Eigen::Vector3d dir = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const Eigen::Vector3d base = base_at(rng, p.linear());
    const auto distance = [&](double s) {
      p.translation() = base + s * dir;
      return distance_at(p);
    };
    // Target distance, or (contact) the depth to move in from first touching.
    const double target = size * (band == 0   ? 0.002 + 0.048 * unit(rng)
                                  : band == 1 ? 0.001 + 0.049 * unit(rng)
                                              : 0.05 + 0.45 * unit(rng));
    if (distance(0) > 0) continue;       // nested, not crossing: another direction
    double lo = 0, hi = reach + target;  // distance(lo) <= goal < distance(hi)
    const double goal = band == 0 ? 0 : target;
    for (int k = 0; k < 60 && hi - lo > 1e-13 * size; ++k) {
      const double mid = (lo + hi) / 2;
      (distance(mid) <= goal ? lo : hi) = mid;
    }
    const double d = distance(band == 0 ? lo - target : hi);
    if (band == 0 ? d == 0 : d > 0 && (band == 1 ? d < 0.05 * size : d >= 0.05 * size)) poses.push_back(p);
  }
  return poses;
}

}  // namespace

std::vector<Eigen::Isometry3d> banded_poses(const Octree& a, const Octree& b, double size, unsigned seed, int count) {
  MeshWorkspace ws;
  make_workspace(a, b, ws);
  const auto distance = [&](const Eigen::Isometry3d& p) {
    MeshDistance d;
    mesh_distance(a, Eigen::Isometry3d::Identity(), b, p, ws, d);
    return d.distance;
  };
  const double reach = std::sqrt(3.0) * (a.nodes[0].half + b.nodes[0].half);  // beyond: apart
  const auto base = [&](std::mt19937&, const Eigen::Matrix3d& R) {
    return Eigen::Vector3d(a.nodes[0].center - R * b.nodes[0].center);
  };
  return banded(distance, base, reach, size, seed, count);
}

std::vector<Eigen::Isometry3d> banded_poses(const Octree& a, const ConvexShape& b, double size, unsigned seed,
                                            int count) {
  const auto distance = [&](const Eigen::Isometry3d& p) {
    MeshDistance d;
    mesh_distance(a, Eigen::Isometry3d::Identity(), b, p, d);
    return d.distance;
  };
  // From a random vertex of A (a small shape at A's centre would sit inside a closed mesh, away
  // from it in every direction), out of A's root cube and beyond the shape's reach and a band.
  double reach_b = 0;
  for (const Eigen::Vector3d& v : b.polytope().vertices) reach_b = std::max(reach_b, v.norm());
  const double reach = 2 * std::sqrt(3.0) * a.nodes[0].half + reach_b + b.radius() + 0.5 * size;
  const auto base = [&](std::mt19937& rng, const Eigen::Matrix3d&) {
    const auto& t = a.triangles[std::uniform_int_distribution<size_t>(0, a.triangles.size() - 1)(rng)];
    return a.vertices[size_t(t[0])];
  };
  return banded(distance, base, reach, size, seed, count);
}

Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cells) {
  Mesh m;
  const Eigen::Vector3d d = hi - lo;
  const auto count = [&](int axis) { return std::max(1, int(std::lround(cells * d[axis] / d.maxCoeff()))); };
  // A face as a grid from corner o along e1 then e2 (its outward normal is e1 x e2).
  const auto face = [&](const Eigen::Vector3d& o, int a1, int a2) {
    const int n1 = count(a1), n2 = count(a2), first = int(m.vertices.size());
    for (int i = 0; i <= n1; ++i)
      for (int j = 0; j <= n2; ++j)
        m.vertices.push_back(o + d[a1] * i / n1 * Eigen::Vector3d::Unit(a1) + d[a2] * j / n2 * Eigen::Vector3d::Unit(a2));
    const auto at = [&](int i, int j) { return first + i * (n2 + 1) + j; };
    for (int i = 0; i < n1; ++i)
      for (int j = 0; j < n2; ++j) {
        m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
        m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      }
  };
  for (int a = 0; a < 3; ++a) {  // e_b x e_c = e_a for the cyclic b, c
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    Eigen::Vector3d top = lo;
    top[a] = hi[a];
    face(top, b, c);
    face(lo, c, b);
  }
  return m;
}

Mesh sphere_mesh(double radius, int rings) {
  Mesh m;
  const int n = rings, around = 2 * rings;
  m.vertices.emplace_back(0, 0, radius);
  for (int i = 1; i < n; ++i)
    for (int j = 0; j < around; ++j) {
      const double th = M_PI * i / n, ph = 2 * M_PI * j / around;
      m.vertices.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::sin(th) * std::sin(ph),
                              radius * std::cos(th));
    }
  m.vertices.emplace_back(0, 0, -radius);
  const int south = int(m.vertices.size()) - 1;
  const auto at = [&](int ring, int j) { return 1 + (ring - 1) * around + (j % around); };
  for (int j = 0; j < around; ++j) {
    m.triangles.push_back({0, at(1, j), at(1, j + 1)});
    m.triangles.push_back({south, at(n - 1, j + 1), at(n - 1, j)});
    for (int i = 1; i + 1 < n; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

Mesh ribbon_mesh(int segments, double twists) {
  Mesh m;
  constexpr double kRadius = 0.3, kTurns = 4, kRise = 0.1, kWidth = 0.05;
  for (int i = 0; i <= segments; ++i) {
    const double s = double(i) / segments, a = 2 * M_PI * kTurns * s;
    const Eigen::Vector3d centre(kRadius * std::cos(a), kRadius * std::sin(a), kRise * kTurns * s);
    const Eigen::Vector3d tangent =
        Eigen::Vector3d(-kRadius * std::sin(a), kRadius * std::cos(a), kRise / (2 * M_PI)).normalized();
    const Eigen::Vector3d out(std::cos(a), std::sin(a), 0);  // (square to the tangent)
    const Eigen::Vector3d across = Eigen::AngleAxisd(2 * M_PI * twists * s, tangent) * out;
    m.vertices.push_back(centre - kWidth / 2 * across), m.vertices.push_back(centre + kWidth / 2 * across);
  }
  for (int i = 0; i < segments; ++i) {
    const int v = 2 * i;
    m.triangles.push_back({v, v + 2, v + 1}), m.triangles.push_back({v + 1, v + 2, v + 3});
  }
  return m;
}

Mesh flattened_mesh(int rings) {
  Mesh m = sphere_mesh(0.5, rings);
  for (Eigen::Vector3d& v : m.vertices) v.z() /= 200;
  return m;
}

Eigen::Matrix3d tilt() { return Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix(); }

Mesh tilted(Mesh m) {
  const Eigen::Matrix3d r = tilt();
  for (Eigen::Vector3d& v : m.vertices) v = r * v;
  return m;
}

Status build_tree(const Mesh& mesh, Octree& out) {
  return mesh.triangles.empty() ? build_octree(mesh.vertices, out) : build_octree(mesh.vertices, mesh.triangles, out);
}

std::vector<Eigen::Vector3d> sample_surface(const Mesh& mesh, int count, unsigned seed) {
  std::vector<double> area(mesh.triangles.size());
  const auto corner = [&](size_t t, int k) { return mesh.vertices[size_t(mesh.triangles[t][size_t(k)])]; };
  for (size_t t = 0; t < area.size(); ++t)
    area[t] = (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0)).norm();
  std::mt19937 rng(seed);
  std::discrete_distribution<size_t> pick(area.begin(), area.end());
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Eigen::Vector3d> points;
  for (int k = 0; k < count; ++k) {
    const size_t t = pick(rng);
    double u = unit(rng), v = unit(rng);
    if (u + v > 1) u = 1 - u, v = 1 - v;
    points.push_back(corner(t, 0) + u * (corner(t, 1) - corner(t, 0)) + v * (corner(t, 2) - corner(t, 0)));
  }
  return points;
}

// Two clouds: every pair of points, |p - q| (the octree's path goes through triangle_distance).
MeshDistance brute_cloud_distance(const Mesh& a, const Mesh& b, const Eigen::Isometry3d& pose) {
  MeshDistance out;
  out.distance = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < b.vertices.size(); ++j) {
    const Eigen::Vector3d q = pose.linear() * b.vertices[j] + pose.translation();
    for (size_t i = 0; i < a.vertices.size(); ++i)
      if (const double d = (a.vertices[i] - q).norm(); d < out.distance)
        out.distance = d, out.point_a = a.vertices[i], out.point_b = q, out.triangle_a = int(i),
        out.triangle_b = int(j);
  }
  out.intersecting = out.distance == 0;
  out.stats.triangle_pairs = long(a.vertices.size() * b.vertices.size());
  return out;
}

MeshDistance brute_distance(const Mesh& a_in, const Mesh& b_in, const Eigen::Isometry3d& pose, ExactDistance exact) {
  using Eigen::Vector3d;
  if (a_in.triangles.empty() && b_in.triangles.empty()) return brute_cloud_distance(a_in, b_in, pose);
  const auto as_mesh = [](const Mesh& m) {
    Mesh out = m;
    if (out.triangles.empty())
      for (size_t k = 0; k < out.vertices.size(); ++k) out.triangles.push_back({int(k), int(k), int(k)});
    return out;
  };
  const Mesh a = as_mesh(a_in), b = as_mesh(b_in);
  std::vector<Vector3d> moved;
  for (const auto& v : b.vertices) moved.push_back(pose.linear() * v + pose.translation());
  // Bounding sphere of each triangle: centroid and largest corner distance.
  const auto spheres = [](const std::vector<Vector3d>& v, const std::vector<std::array<int, 3>>& tris,
                          std::vector<Vector3d>& c, std::vector<double>& r) {
    for (const auto& t : tris) {
      const Vector3d m = (v[t[0]] + v[t[1]] + v[t[2]]) / 3;
      c.push_back(m);
      r.push_back(std::max({(v[t[0]] - m).norm(), (v[t[1]] - m).norm(), (v[t[2]] - m).norm()}) * (1 + 1e-12));
    }
  };
  std::vector<Vector3d> ca, cb;
  std::vector<double> ra, rb;
  spheres(a.vertices, a.triangles, ca, ra);
  spheres(moved, b.triangles, cb, rb);
  // B's spheres in flat arrays: the skip test (squared: |c| > best + ra + rb) runs n^2 times.
  std::vector<double> bx(cb.size()), by(cb.size()), bz(cb.size());
  for (size_t j = 0; j < cb.size(); ++j) bx[j] = cb[j].x(), by[j] = cb[j].y(), bz[j] = cb[j].z();
  // With `exact`, pairs within `margin` of the least double distance are kept as candidates
  // and the answer is the least exact distance among them (the double distance only prunes).
  double margin = 0;
  if (exact) {
    for (const auto& v : a.vertices) margin = std::max(margin, v.cwiseAbs().maxCoeff());
    for (const auto& v : moved) margin = std::max(margin, v.cwiseAbs().maxCoeff());
    margin *= 1e-11;  // (the double distance is within 64 eps of the coordinates: TriangleOracle)
  }
  struct Candidate {
    double d;
    size_t i, j;
    Vector3d p, q;
  };
  std::vector<Candidate> candidates;
  MeshDistance out;
  out.distance = std::numeric_limits<double>::infinity();
  const auto corners_a = [&](size_t i, Vector3d (&s)[3]) {
    for (int k = 0; k < 3; ++k) s[k] = a.vertices[size_t(a.triangles[i][k])];
  };
  const auto corners_b = [&](size_t j, Vector3d (&t)[3]) {
    for (int k = 0; k < 3; ++k) t[k] = moved[size_t(b.triangles[j][k])];
  };
  for (size_t i = 0; i < a.triangles.size() && out.distance > 0; ++i) {
    Vector3d s[3];
    corners_a(i, s);
    for (size_t j = 0; j < b.triangles.size(); ++j) {
      const double dx = bx[j] - ca[i].x(), dy = by[j] - ca[i].y(), dz = bz[j] - ca[i].z(),
                   reach = out.distance + margin + ra[i] + rb[j];
      if (dx * dx + dy * dy + dz * dz > reach * reach) continue;
      Vector3d t[3], p, q;
      corners_b(j, t);
      ++out.stats.triangle_pairs;
      const double d = triangle_distance(s, t, p, q);
      const bool met = d == 0 && (!exact || exact(s, t) == 0);  // (they meet: nothing is nearer)
      if (exact && !met && d <= out.distance + margin) candidates.push_back({d, i, j, p, q});
      if (d < out.distance || met) {
        out.distance = d, out.point_a = p, out.point_b = q;
        out.triangle_a = int(i), out.triangle_b = int(j);
        if (met) {
          candidates.clear();
          break;
        }
      }
    }
  }
  if (exact && out.distance > 0) {
    const double least = out.distance;  // (of the double distances)
    out.distance = std::numeric_limits<double>::infinity();
    for (const Candidate& c : candidates) {
      if (c.d > least + margin) continue;
      Vector3d s[3], t[3];
      corners_a(c.i, s), corners_b(c.j, t);
      if (const double e = exact(s, t); e < out.distance)
        out.distance = e, out.point_a = c.p, out.point_b = c.q, out.triangle_a = int(c.i), out.triangle_b = int(c.j);
    }
  }
  out.intersecting = out.distance == 0;
  out.stats.candidates_a = int(a.triangles.size()), out.stats.candidates_b = int(b.triangles.size());
  return out;
}

Mesh bumpy_sphere(int rings) {
  Mesh m;
  const int n = rings;  // n rings of 2n quads: 4 n^2 triangles
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const double th = M_PI * i / n, ph = M_PI * j / n, r = 0.08 * (1 + 0.2 * std::sin(5 * th) * std::cos(3 * ph));
      m.vertices.emplace_back(r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th));
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const int a = i * 2 * n + j, b = i * 2 * n + (j + 1) % (2 * n), c = a + 2 * n, d = b + 2 * n;
      m.triangles.push_back({a, d, b}), m.triangles.push_back({a, c, d});  // (wound outward)
    }
  return m;
}

Mesh demo_mesh(const std::string& name, std::string& source) {
  Mesh mesh;
  std::string error;
  namespace fs = std::filesystem;
  const fs::path shared = fs::path(MINKSUM_SHARED_DATA) / name;  // (not searched from the working directory)
  if (fs::exists(shared) && read_mesh(shared.string(), mesh, error)) {
    source = fs::weakly_canonical(shared).string();
    return mesh;
  }
  // Else a generated mesh of the named bunny's size (as many triangles, as wide), so that what
  // runs on it costs what it was written to cost.
  const int triangles = name == "bun_zipper.ply" ? 69451 : name == "bun_zipper_res2.ply" ? 16301
                        : name == "bun_zipper_res3.ply" ? 3851 : 948;
  const int rings = int(std::lround(std::sqrt(triangles / 4.0)));
  source = "a generated bumpy sphere of " + std::to_string(4 * rings * rings) + " triangles (no " + shared.string() + ")";
  return bumpy_sphere(rings);
}

}  // namespace minksum::tools
