// The command-line program's commands that live outside main.cpp.
#pragma once

#include <string>

namespace minksum::cli {

/// Prints "minksum: what (see minksum --help)" on stderr and returns exit code 2.
int usage_error(const std::string& what);

/// minksum distance [MESH_A MESH_B] [--pose P] [--poses FILE] [--json] [--brute]
int cmd_distance(int argc, char** argv);

/// minksum haptics [--tool box|icosa|MESH] [--scene MESH] [--seconds S] [--rate HZ]
/// [--realtime] [--plot out.png] [--json]
int cmd_haptics(int argc, char** argv);

}  // namespace minksum::cli
