// The command-line program's commands that live outside main.cpp.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace minksum::cli {

/// Prints "minksum: what (see minksum --help)" on stderr and returns exit code 2.
int usage_error(const std::string& what);

/// Parses exactly `count` finite numbers (`what` names the option, `layout` lists them).
bool parse_numbers(const std::string& text, const std::string& what, const std::string& layout, size_t count,
                   std::vector<double>& v, std::string& error);

/// The rotation of the unit quaternion q[0..3] = (w, x, y, z); false if |q| is not 1 (1e-6).
bool unit_quaternion(const double* q, Eigen::Matrix3d& rotation, std::string& error);

/// Parses "qw qx qy qz tx ty tz" (a unit quaternion, then a translation) into a pose.
bool parse_pose(const std::string& text, const std::string& what, Eigen::Isometry3d& pose, std::string& error);

/// Reads one pose ("qw qx qy qz tx ty tz") per line of `file`, skipping blank lines and
/// '#' comments; false with "file:line: why" (or "file: no pose").
bool read_poses(const std::string& file, std::vector<Eigen::Isometry3d>& poses, std::string& error);

/// minksum distance [MESH_A MESH_B] [--pose P] [--poses FILE [--coherent]] [--json] [--brute]
int cmd_distance(int argc, char** argv);

/// minksum haptics [--tool box|icosa|MESH] [--scene MESH|bunny_full] [--seconds S] [--rate HZ]
/// [--realtime] [--plot out.png] [--trace out.csv] [--json]
int cmd_haptics(int argc, char** argv);

}  // namespace minksum::cli
