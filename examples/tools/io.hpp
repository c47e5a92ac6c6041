// File input and output of the command-line tools (the library itself does no I/O).
#pragma once

#include <minksum/sum.hpp>

#include <string>
#include <vector>

namespace minksum::tools {

/// Reads the vertices of an OFF, OBJ, PLY (ASCII or binary little-endian) or plain "x y z"
/// text file. On failure returns false and sets `error` to "file:line: what is wrong".
bool read_points(const std::string& path, std::vector<Eigen::Vector3d>& points,
                 std::string& error);

/// Writes a sum as an OFF, OBJ or PLY mesh, chosen by the file extension.
bool write_mesh(const std::string& path, const MinkowskiSum& sum, std::string& error);

}  // namespace minksum::tools
