#include "ties.hpp"

#include <algorithm>
#include <array>
#include <limits>

#include "exact_distance.hpp"

namespace minksum::test::ties {

using Eigen::Vector3d;

double lattice(std::mt19937_64& rng, int range, int bits) {
  const long span = long(range) << bits;
  return std::ldexp(double(std::uniform_int_distribution<long>(-span, span)(rng)), -bits);
}

Vector3d lattice_point(std::mt19937_64& rng, int range, int bits) {
  return {lattice(rng, range, bits), lattice(rng, range, bits), lattice(rng, range, bits)};
}

Eigen::Matrix3d quarter_turn(std::mt19937_64& rng) {
  // The 24: a permutation of the axes (6) times the signs of the first two (4); the third sign
  // makes the determinant +1.
  static const int kPerm[6][3] = {{0, 1, 2}, {1, 2, 0}, {2, 0, 1}, {1, 0, 2}, {0, 2, 1}, {2, 1, 0}};
  const int code = int(rng() % 24);
  const int* perm = kPerm[code / 4];
  const double sign[3] = {code & 1 ? -1.0 : 1.0, code & 2 ? -1.0 : 1.0, 1};
  Eigen::Matrix3d r = Eigen::Matrix3d::Zero();
  for (int k = 0; k < 3; ++k) r(k, perm[k]) = sign[k];
  if (r.determinant() < 0) r.row(2) = -r.row(2);  // a proper rotation
  return r;
}

void touching_shapes(std::mt19937_64& rng, bool boxes, ConvexShape& a, ConvexShape& b) {
  if (boxes) {
    const auto [x, y] = touching_boxes(rng);
    shape_from_box(x, a), shape_from_box(y, b);
  } else {
    const auto [x, t] = touching_box_triangle(rng);
    shape_from_box(x, a), shape_from_triangle(t, b);
  }
}

Box lattice_box(std::mt19937_64& rng, int range, int bits) {
  Box b;
  b.center = lattice_point(rng, range, bits);
  for (int d = 0; d < 3; ++d) b.half_extents[d] = std::abs(lattice(rng, range, bits)) + std::ldexp(1.0, -bits);
  b.rotation = rng() % 3 ? quarter_turn(rng) : Eigen::Matrix3d::Identity();
  return b;
}

Triangle lattice_triangle(std::mt19937_64& rng, int range, int bits) {
  for (;;) {
    Triangle t{lattice_point(rng, range, bits), lattice_point(rng, range, bits), lattice_point(rng, range, bits)};
    if ((t.b - t.a).cross(t.c - t.a) != Vector3d::Zero()) return t;  // exact on the lattice
  }
}

namespace {

// A world axis and side of A: the outward unit normal of one of its faces and the face's
// in-plane axes (all exact: A is quarter-turned).
struct Face {
  Vector3d normal, u, v, centre;
  double hu, hv;
};

Face face_of(const Box& a, std::mt19937_64& rng) {
  const int axis = int(rng() % 3), side = rng() % 2 ? 1 : -1;
  const int iu = (axis + 1) % 3, iv = (axis + 2) % 3;
  return {side * a.rotation.col(axis), a.rotation.col(iu),
          a.rotation.col(iv),          a.center + side * a.half_extents[axis] * a.rotation.col(axis),
          a.half_extents[iu],          a.half_extents[iv]};
}

// A lattice point of A's face: inside it, on an edge, or at a corner.
Vector3d on_face(const Face& f, std::mt19937_64& rng) {
  const auto coordinate = [&](double h) {
    switch (rng() % 4) {
      case 0:
        return h;
      case 1:
        return -h;
      default:
        return std::ldexp(std::trunc(std::ldexp(h, 4) * std::uniform_real_distribution<double>(-1, 1)(rng)), -4);
    }
  };
  return f.centre + coordinate(f.hu) * f.u + coordinate(f.hv) * f.v;
}

}  // namespace

std::pair<Box, Box> touching_boxes(std::mt19937_64& rng) {
  const Box a = lattice_box(rng, 4, 3);
  const Face f = face_of(a, rng);
  Box b = lattice_box(rng, 4, 3);
  b.rotation = quarter_turn(rng);
  // B's extent along A's face normal (exact: B is quarter-turned too).
  double along = 0;
  for (int d = 0; d < 3; ++d) along += b.half_extents[d] * std::abs(f.normal.dot(b.rotation.col(d)));
  // Face on face: B's centre above a point of A's face (its patch may overlap A's or only
  // touch it at an edge or a corner: the point may be A's edge or corner).
  b.center = on_face(f, rng) + along * f.normal;
  return {a, b};
}

std::pair<Box, Triangle> touching_box_triangle(std::mt19937_64& rng) {
  const Box a = lattice_box(rng, 4, 3);
  const Face f = face_of(a, rng);
  const Vector3d p = on_face(f, rng);
  Triangle t;
  t.a = p;
  if (rng() % 4 == 1) {  // an edge crossing one of the face's edges, from outside the box
    const Vector3d m = f.centre + f.hu * f.u + lattice(rng, 1, 3) * f.hv * f.v;  // on the edge towards +u
    const Vector3d w = f.normal - f.u;  // out over the face, and out over the side face
    return {a, Triangle{m + w, m - w, m + f.normal + f.u}};
  }
  if (rng() % 4 == 0) {  // lying in the face's plane
    t.b = p + lattice(rng, 3, 2) * f.u + lattice(rng, 3, 2) * f.v;
    t.c = p + lattice(rng, 3, 2) * f.u + lattice(rng, 3, 2) * f.v;
    if ((t.b - t.a).cross(t.c - t.a) == Vector3d::Zero()) t.c = p + f.u + 2 * f.v, t.b = p + 2 * f.u;
  } else {  // a corner on the face, the others above it
    t.b = p + (1 + std::abs(lattice(rng, 2, 2))) * f.normal + lattice(rng, 2, 2) * f.u + lattice(rng, 2, 2) * f.v;
    t.c = p + (1 + std::abs(lattice(rng, 2, 2))) * f.normal + lattice(rng, 2, 2) * f.u + lattice(rng, 2, 2) * f.v;
    if ((t.b - t.a).cross(t.c - t.a) == Vector3d::Zero()) t.c += f.u;
  }
  return {a, t};
}

std::pair<Triangle, Triangle> touching_triangles(std::mt19937_64& rng) {
  const Triangle s = lattice_triangle(rng, 4, 2);
  const Vector3d n = (s.b - s.a).cross(s.c - s.a);  // exact: small lattice numbers
  Vector3d p;
  switch (rng() % 5) {
    case 4: {  // an edge through the midpoint of an edge, crossing the plane there
      const Vector3d m = (s.a + s.b) / 2, w = n + lattice_point(rng, 1, 2);
      return {s, Triangle{m + w, m - w, m + n + w}};
    }
    case 0:
      p = s.b;
      break;  // a shared corner
    case 1:
      p = (s.a + s.c) / 2;
      break;  // on an edge
    case 2:
      p = (s.a + s.b + 2 * s.c) / 4;
      break;    // inside the face
    default: {  // coplanar, overlapping
      const Vector3d q = (s.a + s.b + s.c * 2) / 4;
      return {s, Triangle{q, q + (s.b - s.a) / 2, q + (s.c - s.a) / 2}};
    }
  }
  // The other corners on one side of s's plane (n . (x - p) > 0, exact).
  Triangle t{p, p + n + lattice_point(rng, 1, 2), p + n + lattice_point(rng, 1, 2)};
  for (Vector3d* x : {&t.b, &t.c})
    if (n.dot(*x - p) <= 0) *x = p + n;
  if ((t.b - t.a).cross(t.c - t.a) == Vector3d::Zero()) t.c = p + 2 * n + (s.b - s.a);
  return {s, t};
}

std::vector<Vector3d> lattice_solid_points(std::mt19937_64& rng, int range, int bits) {
  std::uniform_int_distribution<int> count(4, 12);
  for (;;) {
    std::vector<Vector3d> pts(size_t(count(rng)));
    for (auto& p : pts) p = lattice_point(rng, range, bits);
    ConvexPolytope P;
    if (polytope_from_points(pts, P) == Status::Ok && !P.flat) return pts;
  }
}

namespace {

// The surface as triangles: each face's loop fanned from its first vertex (one side of a flat
// polytope: its two faces are the same polygon).
std::vector<std::array<Vector3d, 3>> surface(const ConvexPolytope& P) {
  std::vector<std::array<Vector3d, 3>> out;
  for (size_t f = 0; f < (P.flat ? 1 : P.faces.size()); ++f) {
    const auto& loop = P.faces[f].loop;
    for (size_t k = 2; k < loop.size(); ++k)
      out.push_back({P.vertices[loop[0]], P.vertices[loop[k - 1]], P.vertices[loop[k]]});
  }
  return out;
}

}  // namespace

double exact_surface_gap(const ConvexPolytope& a, const ConvexPolytope& b) {
  const auto sa = surface(a), sb = surface(b);
  // Bounding spheres about the centroids; the pairs in increasing order of the lower bound that
  // the spheres give, so that the least exact distance comes early and ends the scan (a pair is
  // skipped only when its bound, with a margin far above rounding, exceeds the least so far).
  const auto sphere = [](const std::array<Vector3d, 3>& t) {
    const Vector3d c = (t[0] + t[1] + t[2]) / 3;
    return std::make_pair(c, std::max({(t[0] - c).norm(), (t[1] - c).norm(), (t[2] - c).norm()}));
  };
  std::vector<std::pair<double, std::pair<int, int>>> order;
  for (size_t i = 0; i < sa.size(); ++i)
    for (size_t j = 0; j < sb.size(); ++j) {
      const auto [ca, ra] = sphere(sa[i]);
      const auto [cb, rb] = sphere(sb[j]);
      order.push_back({(ca - cb).norm() - ra - rb, {int(i), int(j)}});
    }
  std::sort(order.begin(), order.end());
  double least = std::numeric_limits<double>::infinity();
  for (const auto& [bound, ij] : order) {
    if (least == 0 || bound > least + 1e-9) break;
    const auto &s = sa[size_t(ij.first)], &t = sb[size_t(ij.second)];
    const Vector3d S[3] = {s[0], s[1], s[2]}, T[3] = {t[0], t[1], t[2]};
    least = std::min(least, exact_triangle_distance(S, T));
  }
  return least;
}

std::vector<Vector3d> corners(const Box& b) {
  std::vector<Vector3d> out;
  for (int k = 0; k < 8; ++k) out.push_back(box_corner(b, k));
  return out;
}

std::vector<Vector3d> corners(const Triangle& t) { return {t.a, t.b, t.c}; }

}  // namespace minksum::test::ties
