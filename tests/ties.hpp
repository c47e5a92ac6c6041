// Tie-heavy inputs shared by the tests: coordinates on a dyadic lattice (k / 2^m, exact in
// float and double, so their sums and differences are exact too), boxes that are aligned or
// turned by quarter turns, and pairs in exact contact (a face resting on a face, a vertex on a
// face, an edge on an edge), where random floats never land.
#pragma once

#include <minksum/minksum.hpp>

#include <random>
#include <vector>

namespace minksum::test::ties {

/// A number k / 2^bits with |k| <= range * 2^bits.
double lattice(std::mt19937_64& rng, int range, int bits);

/// A point of lattice coordinates.
Eigen::Vector3d lattice_point(std::mt19937_64& rng, int range, int bits);

/// One of the 24 rotations that map the axes onto the axes (signed permutations, det +1).
Eigen::Matrix3d quarter_turn(std::mt19937_64& rng);

/// A box with lattice centre and half extents (at least 2^-bits), aligned or quarter-turned.
Box lattice_box(std::mt19937_64& rng, int range, int bits);

/// A triangle of lattice corners that are not collinear.
Triangle lattice_triangle(std::mt19937_64& rng, int range, int bits);

/// Two boxes in exact contact, each quarter-turned: B's face on A's face, over a patch, along an
/// edge or at a corner (B's centre lies above a point of A's face, its edge or its corner).
std::pair<Box, Box> touching_boxes(std::mt19937_64& rng);

/// A box and a triangle in exact contact: a corner of the triangle on a face of the box (inside
/// it, on its edge or at its corner), the rest outside; the triangle lying in the face's plane;
/// or an edge of the triangle crossing an edge of the box from outside.
std::pair<Box, Triangle> touching_box_triangle(std::mt19937_64& rng);

/// Two triangles in exact contact: a shared corner, a corner of one on the other's edge or face
/// (the rest on one side), coplanar and overlapping, or an edge through the midpoint of an edge.
std::pair<Triangle, Triangle> touching_triangles(std::mt19937_64& rng);

/// A pair in exact contact as prepared shapes, in world coordinates: touching_boxes, or with
/// `boxes` false touching_box_triangle.
void touching_shapes(std::mt19937_64& rng, bool boxes, ConvexShape& a, ConvexShape& b);

/// 4 to 12 points of lattice coordinates (within +-range, steps 2^-bits), not all in one plane.
std::vector<Eigen::Vector3d> lattice_solid_points(std::mt19937_64& rng, int range, int bits);

/// The least exact distance (exact_triangle_distance) between the surfaces of two polytopes,
/// their faces fanned into triangles: their distance when apart, 0 when the surfaces meet (when
/// they do not, one may still hold the other).
double exact_surface_gap(const ConvexPolytope& a, const ConvexPolytope& b);

/// A box's corners (box_corner order).
std::vector<Eigen::Vector3d> corners(const Box& b);

/// A triangle's corners.
std::vector<Eigen::Vector3d> corners(const Triangle& t);

}  // namespace minksum::test::ties
