// File input and output of the command-line tools (the library itself does no I/O).
#pragma once

#include <minksum/sum.hpp>

#include <array>
#include <istream>
#include <string>
#include <vector>

namespace minksum::tools {

/// False with "path: is a directory, not a file" for a directory (which opens, then reads as empty).
bool readable_file(const std::string& path, std::string& error);

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

/// Writes a sum as an OFF, OBJ or PLY mesh, chosen by the file extension.
bool write_mesh(const std::string& path, const MinkowskiSum& sum, std::string& error);

}  // namespace minksum::tools
