// minksum.Shape: the prepared convex shape (minksum/shape.hpp) built from NumPy arrays.

#include <minksum/shape.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/stl.h>

#include <cmath>

namespace minksum::python {

namespace {

ConvexShape built(Status s, ConvexShape&& shape, const char* what) {
  check(s, what);
  return std::move(shape);
}

// A rounded shape's lengths, refused by the library (InvalidArgument): which one, and its value.
ConvexShape rounded(Status s, ConvexShape&& shape, const char* what, double half_length, double radius, bool added) {
  const auto text = [](double x) { return std::string(py::repr(py::float_(x))); };
  if (s == Status::InvalidArgument && !(half_length >= 0 && std::isfinite(half_length)))
    raise(s, std::string(what) + ": half_length must be >= 0 and finite, got " + text(half_length));
  if (s == Status::InvalidArgument)
    raise(s, std::string(what) + ": radius must be " + (added ? ">= 0" : "> 0") + " and finite, got " + text(radius));
  return built(s, std::move(shape), what);
}

ConvexShape from_points(const py::handle& points) {
  ConvexShape out;
  const std::vector<Eigen::Vector3d> p = points_of(points, "points");
  return built(shape_from_points(p, out), std::move(out), "Shape.from_points");
}

ConvexShape from_mesh(const py::handle& vertices, const std::vector<std::vector<int>>& faces) {
  ConvexShape out;
  const std::vector<Eigen::Vector3d> v = points_of(vertices, "vertices");
  return built(shape_from_mesh(v, faces, out), std::move(out), "Shape.from_mesh");
}

ConvexShape box(const py::handle& half_extents, const py::handle& center, const py::handle& rotation) {
  Box b;
  b.half_extents = vector_of(half_extents, "half_extents");
  if (!center.is_none()) b.center = vector_of(center, "center");
  if (!rotation.is_none()) b.rotation = matrix_of(rotation, "rotation");
  ConvexShape out;
  return built(shape_from_box(b, out), std::move(out), "Shape.box");
}

ConvexShape triangle(const py::handle& corners) {
  const std::vector<Eigen::Vector3d> c = points_of(corners, "corners");
  if (c.size() != 3) refuse("corners", "expected a (3, 3) array, got " + std::to_string(c.size()) + " rows");
  ConvexShape out;
  return built(shape_from_triangle({c[0], c[1], c[2]}, out), std::move(out), "Shape.triangle");
}

py::array_t<int> input_index_of(const ConvexShape& s) {
  const ConvexPolytope& p = s.polytope();
  py::array_t<int> out(py::ssize_t(p.vertices.size()));
  int* d = out.mutable_data();
  for (size_t k = 0; k < p.vertices.size(); ++k) d[k] = p.input_index.size() == p.vertices.size() ? p.input_index[k] : int(k);
  return out;
}

py::tuple faces_of(const ConvexShape& s) {
  const ConvexPolytope& p = s.polytope();
  py::array_t<int> start(py::ssize_t(p.faces.size() + 1));
  py::array_t<double> planes({py::ssize_t(p.faces.size()), py::ssize_t(4)});
  std::vector<int> loops;
  int* first = start.mutable_data();
  double* plane = planes.mutable_data();
  for (size_t f = 0; f < p.faces.size(); ++f) {
    first[f] = int(loops.size());
    loops.insert(loops.end(), p.faces[f].loop.begin(), p.faces[f].loop.end());
    for (int c = 0; c < 3; ++c) plane[4 * f + size_t(c)] = p.faces[f].normal[c];
    plane[4 * f + 3] = p.faces[f].offset;
  }
  first[p.faces.size()] = int(loops.size());
  return py::make_tuple(planes, start, py::array_t<int>(py::ssize_t(loops.size()), loops.data()));
}

}  // namespace

void register_shapes(py::module_& m) {
  py::class_<ConvexShape>(m, "Shape",
                          "An immutable convex shape in its body frame: a core (a polytope, box, triangle, point or segment)\n"
                          "swept by a ball of `radius`. Built and checked once; every query places it by a pose.\n"
                          "Copies share the same read-only data.")
      .def_static("from_points", &from_points, py::arg("points"),
                  "The convex hull of an (n, 3) point array (exact; duplicates dropped, coplanar points give a flat shape).")
      .def_static("from_mesh", &from_mesh, py::arg("vertices"), py::arg("faces"),
                  "A shape from an explicit convex mesh: vertices (n, 3) and faces as vertex loops (any orientation),\n"
                  "checked closed, planar and convex.")
      .def_static("box", &box, py::arg("half_extents") = py::make_tuple(1.0, 1.0, 1.0), py::arg("center") = py::none(),
                  py::arg("rotation") = py::none(),
                  "A box: center + rotation @ (s * half_extents) for s in [-1, 1]^3 (its corners in box_corner order).")
      .def_static("triangle", &triangle, py::arg("corners"), "A triangle (a flat shape) from a (3, 3) array of its corners.")
      .def_static(
          "sphere",
          [](double radius) {
            ConvexShape out;
            return rounded(shape_from_sphere(radius, out), std::move(out), "Shape.sphere", 0, radius, false);
          },
          py::arg("radius"), "A ball of `radius` about the body origin.")
      .def_static(
          "capsule",
          [](double half_length, double radius) {
            ConvexShape out;
            return rounded(shape_from_capsule(half_length, radius, out), std::move(out), "Shape.capsule", half_length, radius,
                           false);
          },
          py::arg("half_length"), py::arg("radius"),
          "The segment from (0, 0, -half_length) to (0, 0, half_length) swept by `radius` (FCL's convention);\n"
          "a half_length of 0 gives the sphere.")
      .def(
          "with_radius",
          [](const ConvexShape& core, double radius) {
            ConvexShape out;
            return rounded(shape_with_radius(core, radius, out), std::move(out), "Shape.with_radius", 0, radius, true);
          },
          py::arg("radius"), "This shape swept by a ball of `radius` (a rounded box, polytope, swept triangle); shares its data.")
      .def_property_readonly("radius", &ConvexShape::radius, "The radius of the ball swept around the core (0: the shape is its core).")
      .def_property_readonly(
          "vertices", [](const ConvexShape& s) { return array_of(s.polytope().vertices.data(), long(s.polytope().vertices.size())); },
          "The core's vertices (n, 3), body frame: the support pairs of sums index them.")
      .def_property_readonly("input_index", &input_index_of,
                             "(n,): the row of the points given (from_points, from_mesh) that each vertex is: a sum's\n"
                             "vertex_pairs and plane_pairs map back to the input through it. A box's corners, a triangle's,\n"
                             "a sphere's centre and a capsule's ends are numbered as built (0, 1, ...).")
      .def_property_readonly("faces", &faces_of,
                             "The core's faces as (planes (F, 4): normal and offset, loop_start (F + 1,), loop_vertex):\n"
                             "face f's loop is loop_vertex[loop_start[f]:loop_start[f + 1]], counter-clockwise from outside.")
      .def("__repr__", [](const ConvexShape& s) {
        return "<minksum.Shape: " + std::to_string(s.polytope().vertices.size()) + " core vertices, radius " +
               std::string(py::repr(py::float_(s.radius()))) + ">";
      });
}

}  // namespace minksum::python
