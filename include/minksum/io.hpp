// File input and output: the strict readers the command-line program uses (OFF, OBJ, PLY, STL
// and plain "x y z" text), and a sum written as a mesh. Not on a real-time path: they allocate.
#pragma once

#include <minksum/sum.hpp>

#include <array>
#include <istream>
#include <string>
#include <vector>

namespace minksum {

/// Reads the vertices of an OFF, OBJ, PLY or plain "x y z" text file (by its extension, else
/// by its content), checking its faces too: read_polygons on the file.
bool read_points(const std::string& path, std::vector<Eigen::Vector3d>& points, std::string& error);

/// Reads the vertices and faces of an OFF, OBJ or PLY file (`format` "off", "obj" or "ply";
/// anything else: told by the content, plain "x y z" text if neither OFF nor PLY). Every
/// count, number and index is checked; polygons are fanned into `triangles` (points and lines
/// dropped; nullptr: check the faces only). On failure returns false and sets `error` to
/// "name:line: what is wrong".
bool read_polygons(std::istream& in, const std::string& name, std::string format, std::vector<Eigen::Vector3d>& points,
                   std::vector<std::array<int, 3>>* triangles, std::string& error);

/// Reads a triangle mesh from an OFF, OBJ, PLY (read_polygons) or STL file (binary or ASCII;
/// three vertices per triangle, as written), chosen by the extension, else by the content.
/// With `cloud_ok`, a file of vertices without faces is a point cloud (no triangles). False
/// with a one-line `error` ("path:line: what is wrong") for a directory, a malformed file, a
/// NaN or Inf coordinate, an index out of range, or no triangles.
bool read_mesh(const std::string& path, std::vector<Eigen::Vector3d>& vertices,
               std::vector<std::array<int, 3>>& triangles, std::string& error, bool cloud_ok = false);

/// Writes a whole sum as an OFF, OBJ or PLY mesh, chosen by the file extension (a rounded sum's
/// point or segment core: its vertices, no faces). False with a one-line `error`, writing
/// nothing, for an empty sum (a failed call's), one without loops (SumParts::Planes or
/// Vertices), or a rounded one (radius > 0: not a polygon mesh) unless `core` (its core is written).
bool write_mesh(const std::string& path, const MinkowskiSum& sum, std::string& error, bool core = false);

}  // namespace minksum
