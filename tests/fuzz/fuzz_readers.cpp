// The file readers on arbitrary bytes, through a file as the CLI reads them: the vertex-file
// reader (OFF, OBJ, PLY, text) and the mesh loader (PLY, OBJ, OFF: the strict reader; STL:
// assimp after a shape check),
// each followed by what the CLI does next (a hull; an octree and a distance query; faceless
// PLY, OFF, OBJ and text files as point clouds). Either a clear error or a result without NaN.
#include "fuzz_common.hpp"

#include <fstream>
#include <string>
#include <unistd.h>

#include <minksum/io.hpp>
#include "support/mesh_io.hpp"

using namespace minksum;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  static const char* kExt[] = {"off", "obj", "ply", "txt", "stl"};
  const char* ext = kExt[data[0] % 5];
  const std::string body(reinterpret_cast<const char*>(data + 1), size - 1);
  std::string error;
  // Both readers take a path, as the CLI gives them (the extension picks the format).
  static const std::string path = "/tmp/minksum_fuzz_" + std::to_string(::getpid()) + ".";
  const std::string file = path + ext;
  std::ofstream(file, std::ios::binary) << body;
  if (data[0] % 2 == 0) {
    std::vector<Eigen::Vector3d> points;
    if (read_points(file, points, error)) {
      for (const auto& p : points)
        if (!fuzz::finite(p)) fuzz::fail("the vertex reader returned a non-finite point");
      ConvexPolytope P;
      polytope_from_points(points, P);
    } else if (error.empty()) {
      fuzz::fail("a failed read without a message");
    }
    return 0;
  }
  // As `minksum distance` reads: a file of vertices without faces is a point cloud.
  tools::Mesh mesh;
  if (!tools::read_mesh(file, mesh, error, true)) {
    if (error.empty()) fuzz::fail("a failed mesh read without a message");
    return 0;
  }
  Octree tree;
  if (tools::build_tree(mesh, tree) != Status::Ok) return 0;  // e.g. NaN
  MeshWorkspace ws;
  make_workspace(tree, tree, ws);
  // B: a copy turned about a generic axis and moved by a fraction of the mesh's size that the
  // input picks (overlapping through apart), so that every bound of the query is exercised.
  double extent = 0;
  for (const auto& t : mesh.triangles)
    for (int k : t) extent = std::max(extent, mesh.vertices[k].cwiseAbs().maxCoeff());
  if (mesh.triangles.empty())
    for (const auto& v : mesh.vertices) extent = std::max(extent, v.cwiseAbs().maxCoeff());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.1 + data[0] / 40.0, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.3, -0.2, 0.1) * extent * (data[size - 1] % 8) / 2.0;
  MeshDistance d;
  if (mesh_distance(tree, Eigen::Isometry3d::Identity(), tree, pose, ws, d) != Status::Ok) return 0;
  if (!(d.distance >= 0 && std::isfinite(d.distance))) fuzz::fail("mesh distance not finite and >= 0");
  // The octree prunes with lower bounds only: it must find what all pairs find.
  if (std::max(mesh.triangles.size(), mesh.triangles.empty() ? mesh.vertices.size() : 0) <= 300) {
    const MeshDistance want = tools::brute_distance(mesh, mesh, pose);
    if (!(std::abs(d.distance - want.distance) <= 1e-12 * (1 + 4 * extent)))
      fuzz::fail("mesh distance differs from all pairs");
  }
  return 0;
}
