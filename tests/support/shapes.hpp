// Test and benchmark shapes: the paper's Table 1 solids and seeded random polytopes.
#pragma once

#include <minksum/kernels.hpp>
#include <minksum/model.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <random>
#include <string>
#include <vector>

namespace minksum::tools {

/// Vertices of the cube [-1, 1]^3.
std::vector<Eigen::Vector3d> cube_points();
/// Vertices of the regular icosahedron (0, +-1, +-phi) and cyclic permutations.
std::vector<Eigen::Vector3d> icosahedron_points();
/// Vertices of the regular dodecahedron (+-1, +-1, +-1), (0, +-1/phi, +-phi) and permutations.
std::vector<Eigen::Vector3d> dodecahedron_points();

/// The generic rotation applied to B in every Table 1 pair: 0.7 rad about (1, 2, 3)/sqrt(14).
Eigen::Matrix3d table1_rotation();

/// One row of the paper's Table 1: operand names and point sets (B already rotated).
struct Table1Pair {
  std::string name;                   ///< e.g. "cube_rotcube"
  std::vector<Eigen::Vector3d> a, b;  ///< vertex sets, exact: every face exactly planar
  std::vector<Eigen::Vector3d> b_body;  ///< B before its turn (b is rotation * b_body, exactly in reals)
  Eigen::Matrix3d rotation;             ///< B's turn, rounded to doubles: pass it as B's pose
};

/// The six pairs of Table 1, in the paper's order, in exact coordinates: the cube, the
/// icosahedron and the pyritohedron of exact_*_points(), near unit size, B turned by the
/// integer matrix of exact_rotated(). Points rounded from an irrational rotation would not be
/// coplanar, and their exact hull would split each face into triangles.
std::vector<Table1Pair> table1_pairs();

/// A rotation about a unit axis by an angle (radians).
Eigen::Matrix3d axis_angle(const Eigen::Vector3d& axis, double angle);

/// Every lane of A and B: Table 1's cube pair as boxes (the unit cube, and B turned by
/// table1_rotation()) in lane 0, and in lane k the pair varied: B turned further by 0.05 k rad
/// about an axis of its own, both boxes stretched and moved, so that no two lanes are alike (32
/// copies of one pair would flatter the branch predictor and the caches).
template <class T, int N>
void fill_table1_cubes(BoxBatch<T, N>& A, BoxBatch<T, N>& B) {
  for (int k = 0; k < N; ++k) {
    Box a, b;
    const double t = double(k);
    a.half_extents = Eigen::Vector3d(1 + 0.01 * t, 1 + 0.02 * std::fmod(3 * t, 7), 1 + 0.015 * std::fmod(5 * t, 11));
    a.center = 0.1 * Eigen::Vector3d(std::sin(t), std::cos(2 * t), std::sin(3 * t));
    b.half_extents = Eigen::Vector3d(1 + 0.02 * std::fmod(2 * t, 5), 1 + 0.01 * t, 1);
    b.rotation = axis_angle(Eigen::Vector3d(std::cos(t), std::sin(t), 0.5), 0.05 * t) * table1_rotation();
    A.set(k, a), B.set(k, b);
  }
  A.count = B.count = N;
}

/// The Table 1 solids with exactly representable coordinates and exactly planar faces, for the
/// exact oracle: an icosahedron (0, +-55, +-89) and cyclic permutations (phi ~ 89/55), and a
/// pyritohedron with h = 21/34 (combinatorially the dodecahedron): 1156 (+-1, +-1, +-1) and
/// (0, +-1870, +-715) and cyclic permutations.
std::vector<Eigen::Vector3d> exact_icosahedron_points();
/// See exact_icosahedron_points().
std::vector<Eigen::Vector3d> exact_dodecahedron_points();

/// The rotation of the unit quaternion (4, 1, 2, 3)/sqrt(30), scaled by 30: an integer matrix,
/// so integer points stay exact.
std::vector<Eigen::Vector3d> exact_rotated(const std::vector<Eigen::Vector3d>& pts);

/// Every point times s.
std::vector<Eigen::Vector3d> scaled(std::vector<Eigen::Vector3d> pts, double s);

/// One pair of a degenerate family: integer coordinates, so that every tie of the family
/// (parallel faces and edges, a face on a face) is exact, and a sum or a difference.
struct DegeneratePair {
  std::string name;                   ///< e.g. "aligned_boxes", "prisms_32"
  std::vector<Eigen::Vector3d> a, b;  ///< vertex sets
  bool difference = false;            ///< A (-) B (the mirrored family), else A (+) B
};

/// The degenerate families, in order: aligned_boxes, boxes_shared_axis (B turned about z by a
/// Pythagorean angle, exact), prisms_8 ... prisms_64 (aligned n-gon prisms, B's polygon a
/// multiple of A's: parallel sides), box_prism, identical, mirrored (A (-) A) and
/// coplanar_faces (B keeps A's upper faces).
constexpr int kDegenerateFamilies = 10;

/// A seeded random member of family `family` (0 ... kDegenerateFamilies - 1).
DegeneratePair degenerate_pair(int family, std::mt19937_64& rng);

/// One fixed member of every family (seed 1): the benchmark's Degenerate rows.
std::vector<DegeneratePair> degenerate_pairs();

/// The rounded-tie families: shapes of rounded coordinates (cos/sin prisms, boxes turned by a
/// rounded angle), whose faces' exact normals are not doubles, in poses that keep their ties:
/// prisms_<n>_rounded (aligned n-gon prisms, n = 8 ... 64, B's polygon A's halved: parallel
/// sides), prisms_16_turned_rounded (B turned about the shared axis by a rounded angle),
/// box_turned_rounded (B turned about z by a non-Pythagorean angle), prism_box_rounded (a
/// 16-gon prism on a box's face) and icosa_copies_rounded (an icosahedron and a copy of another
/// size, each turned by one rotation and rounded apart: every face within rounding of parallel
/// to its twin, near-ties).
constexpr int kRoundedFamilies = 8;

/// One member of rounded family `family` (0 ... kRoundedFamilies - 1), its sizes and angles
/// from a seeded generator.
DegeneratePair rounded_pair(int family, std::mt19937_64& rng);

/// One fixed member of every rounded family (seed 1): the benchmark's Degenerate/*_rounded rows.
std::vector<DegeneratePair> rounded_pairs();

/// An n-gon prism of radius r between heights z0 and z1, its polygon turned by `phase` (rad):
/// vertices (r cos t, r sin t, z), rounded as a user computes them.
std::vector<Eigen::Vector3d> cos_sin_prism(int n, double r, double z0, double z1, double phase = 0);

/// The corners of a box of half extents h turned about z by `angle` (rounded cos and sin).
std::vector<Eigen::Vector3d> turned_box(const Eigen::Vector3d& h, double angle);

/// Applies R to every point.
std::vector<Eigen::Vector3d> rotated(const std::vector<Eigen::Vector3d>& pts, const Eigen::Matrix3d& R);

/// n points uniformly on the unit sphere, from a seeded generator.
std::vector<Eigen::Vector3d> sphere_points(int n, unsigned seed);

/// A seeded random box: centre in [-spread, spread]^3, a random rotation, half extents in
/// [0.05, max_half].
Box random_box(std::mt19937_64& rng, double spread, double max_half = 1.5);

/// A seeded random triangle: corners in a unit cube around a centre in [-spread, spread]^3.
Triangle random_triangle(std::mt19937_64& rng, double spread);

/// Seeded smooth relative motion, the same for every method of a benchmark: B's centre (in
/// A's frame) swings between `near` and `far` from A's along a slowly turning direction,
/// moving at most `step` per tick, while B turns by at most 0.5 degree per tick about a
/// slowly turning axis. With near inside contact and far outside, it passes in and out of
/// contact about every 2,000 ticks.
std::vector<Eigen::Isometry3d> trajectory(unsigned seed, int ticks, double near, double far, double step);

/// A pair that meets face to face (or edge to face): A at rest, B lowered onto A's top face
/// (A's largest z) along z, each in its body frame; a box is built by shape_from_box, as a
/// user writes it. Sizes are near 1.
struct FacePair {
  std::string name;
  std::vector<Eigen::Vector3d> a, b;  ///< the points of each (a box's: its corners)
  bool a_is_box = false, b_is_box = false;
  Box box_a, box_b;  ///< the boxes, where one is
};

/// The families: boxes, n-gon prisms (n = 8, 16, 32, 64), a box on a prism's cap, a
/// polytope's flat face on a box, and a box's edge resting along a box's face.
std::vector<FacePair> face_pairs();

/// B's pose in A's frame at tick k of a slide of `ticks`: B's lowest point `gap` above A's top
/// (0: touching, negative: pressed), its centre circling within 0.25 of A's axis, and, if
/// `rocking`, B tilted by up to 1e-3 rad about a turning horizontal axis.
Eigen::Isometry3d face_pose(const FacePair& p, int k, int ticks, double gap, bool rocking);

}  // namespace minksum::tools
