// Triangle-mesh input of the command-line tools, STL through assimp (the library takes arrays).
#pragma once

#include <minksum/mesh.hpp>
#include <array>
#include <string>
#include <vector>

namespace minksum::tools {

/// A triangle mesh as the library's octree takes it; no triangles: a point cloud.
struct Mesh {
  std::vector<Eigen::Vector3d> vertices;      ///< positions
  std::vector<std::array<int, 3>> triangles;  ///< vertex indices
};

/// minksum::read_mesh into a Mesh.
bool read_mesh(const std::string& path, Mesh& mesh, std::string& error, bool cloud_ok = false);

/// The octree of a mesh, or of a point cloud (a Mesh without triangles).
Status build_tree(const Mesh& mesh, Octree& out);

/// `count` points on the mesh's surface, uniform by area (seeded).
std::vector<Eigen::Vector3d> sample_surface(const Mesh& mesh, int count, unsigned seed);

/// The demo mesh: `name` (a Stanford bunny) in ../shared/data beside the source tree, wherever
/// it is run from; else a generated bumpy sphere with as many triangles as that bunny (0.19
/// across), never a larger mesh. `source` says which one was used.
Mesh demo_mesh(const std::string& name, std::string& source);

/// A bumpy sphere 0.19 across: `rings` rings of 2 `rings` quads, 4 rings^2 triangles, wound
/// counter-clockwise seen from outside (a haptic tool's contact reads the outside from it).
Mesh bumpy_sphere(int rings);

/// A mesh of Debian's libcgal-demo, data/meshes/`name` in its data.tar.gz (e.g. "camel.off"),
/// moved and scaled so that its bounding box is centred at the origin with diagonal 1; false if
/// the package or the member is absent.
bool cgal_demo_mesh(const std::string& name, Mesh& mesh);

/// The vertex list of libcgal-demo's data/meshes/`name`, as given (what a user's
/// `Shape.from_points` or the CLI would read from it); false if the package or the member is absent.
bool cgal_demo_points(const std::string& name, std::vector<Eigen::Vector3d>& points);

/// Ten CAD parts of libcgal-demo (anchor.off ... turbine.off): machined shapes, whose flat faces
/// and cylinders put many points exactly or nearly on one plane.
std::vector<std::string> cad_parts();

/// Seeded poses of mesh B against mesh A in three bands of `size` (say the smaller mesh's
/// bounding-box diagonal): the first third intersect (up to 5 % deep), the second are apart by
/// less than 5 %, the rest by 5-50 %. Each has a random rotation and direction; B is moved along
/// the direction by bisection on mesh_distance to a random distance in its band.
std::vector<Eigen::Isometry3d> banded_poses(const Octree& a, const Octree& b, double size, unsigned seed, int count);

/// The same for a convex shape B (its origin moved along the direction from A's centre), by
/// the shape form of mesh_distance.
std::vector<Eigen::Isometry3d> banded_poses(const Octree& a, const ConvexShape& b, double size, unsigned seed,
                                            int count);

/// The band of the k-th of `count` banded poses: 0 contact, 1 near (< 5 %), 2 far.
inline int band_of(int k, int count) { return 3 * k / count; }

/// The surface of the box [lo, hi], each face a grid of squares wound outward, about `cells`
/// along its longest edge (at least one along each): a thin box is a sheet.
Mesh box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int cells);

/// A UV sphere about the origin: a vertex at each pole, rings - 1 circles of 2 rings vertices,
/// 4 rings (rings - 1) triangles.
Mesh sphere_mesh(double radius, int rings);

/// A twisted ribbon of slivers: a strip 0.05 wide wound as a helix about the z axis (radius 0.3,
/// 4 turns, 0.1 apart), turning about its centre line `twists` times along it; `segments` steps
/// along, two triangles each (at 4,000 steps each is 0.002 long and 0.05 across: 25 to 1).
Mesh ribbon_mesh(int segments, double twists);

/// A closed surface flattened to 1:200: sphere_mesh(0.5, rings) with z scaled by 1/200 (a lens 1
/// across and 0.005 thick).
Mesh flattened_mesh(int rings);

/// The turn of `tilted`: 0.7 rad about (1, 2, 3), off every coordinate axis.
Eigen::Matrix3d tilt();

/// The mesh turned by tilt(): boxes aligned with the mesh's axes fit a thin shape worst there
/// (its lens or ribbon no longer lies along them).
Mesh tilted(Mesh m);

/// All-pairs triangle distance (for checking mesh_distance): every pair is enumerated, a pair
/// is skipped only if its bounding spheres are already farther apart than the best distance.
/// A point cloud's points are zero-area triangles; two clouds: plain point-point distances.
/// With `exact` (the tests pass test::exact_triangle_distance, GMP rationals: not the library),
/// the distance is the least exact one over the pairs whose double distance is within 1e-11 of
/// the coordinates' reach of the least: the library's triangle_distance (within 64 eps of the
/// coordinates, tests/test_triangle_oracle.cpp) only prunes.
using ExactDistance = double (*)(const Eigen::Vector3d (&)[3], const Eigen::Vector3d (&)[3]);
MeshDistance brute_distance(const Mesh& a, const Mesh& b, const Eigen::Isometry3d& pose, ExactDistance exact = nullptr);

}  // namespace minksum::tools
