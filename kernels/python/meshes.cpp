// Triangle meshes and point clouds (minksum/mesh.hpp) and the file readers (minksum/io.hpp). The
// mesh queries run without the GIL: a workspace or a cache is the caller's, one per thread.

#include <minksum/io.hpp>
#include <minksum/mesh.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/stl.h>

namespace minksum::python {

namespace {

Octree mesh_of(const py::handle& vertices, const py::handle& triangles, int leaf_size) {
  std::vector<Eigen::Vector3d> v = points_of(vertices, "vertices");
  const std::vector<std::array<int, 3>> t = triangles_of(triangles, "triangles", long(v.size()));
  OctreeOptions options;
  options.leaf_size = leaf_size;
  Octree out;
  Status s;
  {
    py::gil_scoped_release unlocked;
    s = build_octree(v, t, out, options);
  }
  if (s == Status::InvalidArgument) raise(s, "Mesh: leaf_size must be at least 1, got " + std::to_string(leaf_size));
  if (s == Status::EmptyMesh) raise(s, "Mesh: no triangles (Mesh.from_points builds a point cloud)");
  check(s, "Mesh");
  return out;
}

Octree cloud_of(const py::handle& points, int leaf_size) {
  const std::vector<Eigen::Vector3d> p = points_of(points, "points");
  OctreeOptions options;
  options.leaf_size = leaf_size;
  Octree out;
  Status s;
  {
    py::gil_scoped_release unlocked;
    s = build_octree(p, out, options);
  }
  if (s == Status::InvalidArgument) raise(s, "Mesh.from_points: leaf_size must be at least 1, got " + std::to_string(leaf_size));
  check(s, "Mesh.from_points");
  return out;
}

// The caller's workspace, or one made for this call (it allocates: reuse one for many calls).
MeshWorkspace& workspace_for(const Octree& a, const Octree& b, MeshWorkspace* given, MeshWorkspace& own) {
  if (given) return *given;
  make_workspace(a, b, own);
  return own;
}

template <class Other>
MeshDistance distance_of(const Octree& a, const py::handle& pose_a, const Other& b, const py::handle& pose_b,
                         MeshWorkspace* workspace, ProximityCache* cache) {
  const Eigen::Isometry3d pa = pose_of(pose_a, "pose_a"), pb = pose_of(pose_b, "pose_b");
  MeshDistance out;
  Status s;
  if constexpr (std::is_same_v<Other, Octree>) {
    MeshWorkspace own;
    MeshWorkspace& ws = workspace_for(a, b, workspace, own);
    py::gil_scoped_release unlocked;
    s = cache ? mesh_distance(a, pa, b, pb, ws, *cache, out) : mesh_distance(a, pa, b, pb, ws, out);
  } else {
    if (workspace) refuse("workspace", "a shape's mesh distance takes none");
    py::gil_scoped_release unlocked;
    s = cache ? mesh_distance(a, pa, b, pb, *cache, out) : mesh_distance(a, pa, b, pb, out);
  }
  check(s, "mesh_distance", {{pa, "pose_a"}, {pb, "pose_b"}});
  return out;
}

MeshContact contact_of(const Octree& a, const py::handle& pose_a, const ConvexShape& tool, const py::handle& pose_tool,
                       MeshWorkspace* workspace) {
  const Eigen::Isometry3d pa = pose_of(pose_a, "pose_a"), pt = pose_of(pose_tool, "pose_tool");
  MeshWorkspace own;
  MeshWorkspace& ws = workspace_for(a, a, workspace, own);
  MeshContact out;
  Status s;
  {
    py::gil_scoped_release unlocked;
    s = mesh_contact(a, pa, tool, pt, ws, out);
  }
  check(s, "mesh_contact", {{pa, "pose_a"}, {pt, "pose_tool"}});
  return out;
}

TimeOfImpact sweep_of(const Octree& a, const py::handle& pose_a, const ConvexShape& tool, const py::handle& t0,
                      const py::handle& t1, double tolerance) {
  const Eigen::Isometry3d pa = pose_of(pose_a, "pose_a"), p0 = pose_of(t0, "t0"), p1 = pose_of(t1, "t1");
  TimeOfImpact out;
  Status s;
  {
    py::gil_scoped_release unlocked;
    s = time_of_impact(a, pa, tool, p0, p1, out, tolerance);
  }
  check(s, "time_of_impact", {{pa, "pose_a"}, {p0, "t0"}, {p1, "t1"}});
  return out;
}

py::array_t<int> triangle_array(const std::vector<std::array<int, 3>>& t) {
  py::array_t<int> out({py::ssize_t(t.size()), py::ssize_t(3)});
  int* d = out.mutable_data();
  for (const auto& tri : t) *d++ = tri[0], *d++ = tri[1], *d++ = tri[2];
  return out;
}

void register_mesh_results(py::module_& m) {
  py::class_<MeshDistance>(m, "MeshDistance", "The answer of a mesh distance query.")
      .def_readonly("distance", &MeshDistance::distance, "The exact minimum distance (0 when they meet).")
      .def_property_readonly(
          "point_a", [](const MeshDistance& d) { return array_of(d.point_a); }, "The closest point on A (world frame).")
      .def_property_readonly(
          "point_b", [](const MeshDistance& d) { return array_of(d.point_b); }, "The closest point on B (world frame).")
      .def_readonly("triangle_a", &MeshDistance::triangle_a, "The triangle of A holding point_a.")
      .def_readonly("triangle_b", &MeshDistance::triangle_b, "The triangle of B holding point_b (-1 for a shape).")
      .def_readonly("intersecting", &MeshDistance::intersecting, "They share a point.");
  py::class_<MeshContact>(m, "MeshContact", "How a convex tool touches a mesh (haptic rendering).")
      .def_readonly("intersecting", &MeshContact::intersecting, "Some triangle has a part inside the tool.")
      .def_readonly("penetration_depth", &MeshContact::penetration_depth, "How far the tool must move along the direction.")
      .def_property_readonly(
          "penetration_direction", [](const MeshContact& c) { return array_of(c.penetration_direction); },
          "The unit push-out direction.")
      .def_property_readonly(
          "point", [](const MeshContact& c) { return array_of(c.point); }, "The part's corner that needs the push most.")
      .def_readonly("triangle", &MeshContact::triangle, "The triangle of that corner.")
      .def_readonly("area", &MeshContact::area, "The parts' total area (0 for a rounded tool).")
      .def_property_readonly(
          "centre", [](const MeshContact& c) { return array_of(c.centre); }, "Their area-weighted centre.")
      .def_readonly("overflow", &MeshContact::overflow, "More triangles overlapped than one call gathers: the first ones count.");
  py::class_<MeshWorkspace>(m, "MeshWorkspace",
                            "Scratch memory for the queries of one pair of meshes (and a tool's contact with the first),\n"
                            "so that they do not allocate. One per thread.")
      .def(py::init([](const Octree& a, const Octree& b) {
             MeshWorkspace ws;
             make_workspace(a, b, ws);
             return ws;
           }),
           py::arg("a"), py::arg("b"));
}

}  // namespace

void register_meshes(py::module_& m) {
  py::class_<Octree, std::shared_ptr<Octree>>(m, "Mesh",
                                              "A triangle mesh (or a point cloud) in its own frame, in an octree built once.")
      .def(py::init(&mesh_of), py::arg("vertices"), py::arg("triangles"), py::arg("leaf_size") = 64,
           "A mesh from vertices (n, 3) and triangles (m, 3) of integer indices. Degenerate triangles and open or\n"
           "non-manifold meshes are accepted.")
      .def_static("from_points", &cloud_of, py::arg("points"), py::arg("leaf_size") = 64,
                  "A point cloud: the distance to it is the distance to its nearest point.")
      .def_property_readonly(
          "vertices", [](const Octree& o) { return array_of(o.vertices.data(), long(o.vertices.size())); }, "(n, 3).")
      .def_property_readonly(
          "triangles", [](const Octree& o) { return triangle_array(o.triangles); }, "(m, 3) (k, k, k for point k of a cloud).")
      .def_readonly("is_cloud", &Octree::points, "Built from a point cloud.");
  register_mesh_results(m);
  m.def("mesh_distance", &distance_of<Octree>, py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"),
        py::arg("workspace") = nullptr, py::arg("cache") = nullptr,
        "The exact minimum distance between two meshes (or clouds), each placed by its pose. Without a workspace,\n"
        "one is made for the call: pass MeshWorkspace(a, b) to reuse it.");
  m.def("mesh_distance", &distance_of<ConvexShape>, py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"),
        py::arg("workspace") = nullptr, py::arg("cache") = nullptr,
        "The exact minimum distance between a mesh and a convex shape (solid: a triangle inside it touches it).");
  m.def("mesh_contact", &contact_of, py::arg("a"), py::arg("pose_a"), py::arg("tool"), py::arg("pose_tool"),
        py::arg("workspace") = nullptr,
        "The contact of a convex tool with a mesh: the push-out direction and depth, the contact centre. Without a\n"
        "workspace, one is made for the call (it allocates): pass a MeshWorkspace (any pair's) to reuse it.");
  m.def("time_of_impact", &sweep_of, py::arg("a"), py::arg("pose_a"), py::arg("tool"), py::arg("t0"), py::arg("t1"),
        py::arg("tolerance") = 0.0,
        "When a convex tool moving from pose t0 to t1 first touches the mesh a, and the triangle it touches.");
  m.def(
      "read_mesh",
      [](const py::handle& file, bool cloud_ok) {
        const std::string path = path_of(file);
        std::vector<Eigen::Vector3d> v;
        std::vector<std::array<int, 3>> t;
        std::string error;
        if (!read_mesh(path, v, t, error, cloud_ok)) throw py::value_error(error);
        return py::make_tuple(array_of(v.data(), long(v.size())), triangle_array(t));
      },
      py::arg("path"), py::arg("cloud_ok") = false,
      "Reads (vertices (n, 3), triangles (m, 3)) from an OFF, OBJ, PLY or STL file. ValueError 'path:line: what is wrong'.");
  m.def(
      "read_points",
      [](const py::handle& file) {
        std::vector<Eigen::Vector3d> p;
        std::string error;
        if (!read_points(path_of(file), p, error)) throw py::value_error(error);
        return array_of(p.data(), long(p.size()));
      },
      py::arg("path"), "Reads the vertices (n, 3) of an OFF, OBJ, PLY or plain 'x y z' text file.");
  m.def(
      "write_mesh",
      [](const py::handle& file, const MinkowskiSum& sum, bool core) {
        std::string error;
        if (!write_mesh(path_of(file), sum, error, core)) throw py::value_error(error);
      },
      py::arg("path"), py::arg("sum"), py::arg("core") = false,
      "Writes a whole sum as an OFF, OBJ or PLY mesh, by the file's extension. ValueError, writing nothing, for an empty\n"
      "sum, one without loops (parts PLANES or VERTICES), or a rounded one unless core=True (its core is written).");
}

}  // namespace minksum::python
