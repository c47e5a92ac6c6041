// Triangle-mesh input of the command-line tools, STL through assimp (the library takes arrays).
#pragma once

#include <minksum/mesh.hpp>
#include <array>
#include <string>
#include <vector>

namespace minksum::tools {

/// A triangle mesh as the library's octree takes it.
struct Mesh {
  std::vector<Eigen::Vector3d> vertices;      ///< positions
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices
};

/// Reads a PLY, OBJ, OFF or STL mesh (polygons are triangulated; points and lines dropped;
/// vertices kept as they are: no welding). STL is read by assimp, the others by read_polygons.
/// On failure returns false and sets `error` to "path: what is wrong".
bool read_mesh(const std::string& path, Mesh& mesh, std::string& error);

/// The demo mesh: `name` in ../shared/data (searched from the working directory up), else
/// data/meshes/bunny00.off from Debian's libcgal-demo (its data.tar.gz), else a generated
/// torus. `source` says which one was used.
Mesh demo_mesh(const std::string& name, std::string& source);

/// A UV sphere about the origin: a vertex at each pole, rings - 1 circles of 2 rings vertices,
/// 4 rings (rings - 1) triangles.
Mesh sphere_mesh(double radius, int rings);

/// All-pairs triangle distance (for checking mesh_distance): every pair is enumerated, a pair
/// is skipped only if its bounding spheres are already farther apart than the best distance.
MeshDistance brute_distance(const Mesh& a, const Mesh& b, const Pose& pose);

}  // namespace minksum::tools
