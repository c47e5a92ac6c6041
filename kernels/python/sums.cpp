// minkowski_sum and minkowski_difference of posed shapes (minksum/sum.hpp), and minksum.Sum, whose
// arrays are flat: planes (F, 4), loops as offsets plus indices.

#include <minksum/query.hpp>
#include <minksum/sum.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

namespace minksum::python {

namespace {

using SumFunction = Status (*)(const ConvexShape&, const Eigen::Isometry3d&, const ConvexShape&, const Eigen::Isometry3d&,
                               MinkowskiSum&, SumParts);

// Operands with more vertices than this together are summed without the GIL (a sum of large
// shapes takes milliseconds); smaller ones hold it, as releasing it would cost a tenth of theirs.
constexpr size_t kUnlockedVertices = 256;

// The sum into `out` (a Sum from an earlier call, refilled in place: its arrays keep their
// capacity, so a loop of sums stops allocating), or into a new Sum.
py::object sum_of(SumFunction f, const char* what, const ConvexShape& a, const py::handle& pose_a, const ConvexShape& b,
                  const py::handle& pose_b, SumParts parts, const py::handle& into) {
  const Eigen::Isometry3d pa = pose_of(pose_a, "pose_a"), pb = pose_of(pose_b, "pose_b");
  py::object result = into.is_none() ? py::cast(MinkowskiSum{}) : py::reinterpret_borrow<py::object>(into);
  if (!py::isinstance<MinkowskiSum>(result)) refuse("out", "expected a minksum.Sum");
  MinkowskiSum& out = py::cast<MinkowskiSum&>(result);
  Status s;
  if (a.polytope().vertices.size() + b.polytope().vertices.size() > kUnlockedVertices) {
    py::gil_scoped_release unlocked;
    s = f(a, pa, b, pb, out, parts);
  } else {
    s = f(a, pa, b, pb, out, parts);
  }
  check(s, what, {{pa, "pose_a"}, {pb, "pose_b"}});
  return result;
}

py::array_t<double> planes_of(const MinkowskiSum& m) {
  py::array_t<double> out({py::ssize_t(m.planes.size()), py::ssize_t(4)});
  double* d = out.mutable_data();
  for (const SumPlane& p : m.planes) *d++ = p.normal.x(), *d++ = p.normal.y(), *d++ = p.normal.z(), *d++ = p.offset;
  return out;
}

// The support pairs (i, j) of the planes or of the vertices, as an (n, 2) array.
template <class Item>
py::array_t<int> pairs_of(const std::vector<Item>& items) {
  py::array_t<int> out({py::ssize_t(items.size()), py::ssize_t(2)});
  int* d = out.mutable_data();
  for (const Item& item : items) *d++ = item.i, *d++ = item.j;
  return out;
}

py::array_t<double> vertices_of(const MinkowskiSum& m) {
  py::array_t<double> out({py::ssize_t(m.vertices.size()), py::ssize_t(3)});
  double* d = out.mutable_data();
  for (const SumVertex& v : m.vertices) *d++ = v.point.x(), *d++ = v.point.y(), *d++ = v.point.z();
  return out;
}

py::array_t<int> ints_of(const std::vector<int>& v) { return py::array_t<int>(py::ssize_t(v.size()), v.data()); }

std::string sum_doc(const char* op) {
  return std::string("(R_A A + t_A) ") + op +
         " (R_B B + t_B) of two shapes, each placed by its pose: planes and vertices in the world frame,\n"
         "support pairs (i, j) indexing a.vertices and b.vertices. parts: SumParts.PLANES skips the vertices and loops,\n"
         "SumParts.VERTICES the loops. Rounded shapes: the sum of the cores, whole, with `radius` the radii added.\n"
         "out: a Sum from an earlier call, refilled in place and returned (a loop of sums then stops allocating).";
}

}  // namespace

void register_sums(py::module_& m) {
  py::class_<MinkowskiSum>(m, "Sum", "A Minkowski sum or difference: facet planes with their support pairs, vertices, and facet loops.")
      .def_property_readonly("planes", &planes_of, "(F, 4): each facet's outward unit normal and offset (n . x <= offset inside).")
      .def_property_readonly(
          "plane_pairs", [](const MinkowskiSum& s) { return pairs_of(s.planes); }, "(F, 2): a support pair (i, j) on each facet.")
      .def_property_readonly("vertices", &vertices_of, "(V, 3): the vertices, sorted by their pairs.")
      .def_property_readonly(
          "vertex_pairs", [](const MinkowskiSum& s) { return pairs_of(s.vertices); }, "(V, 2): each vertex's support pair (i, j).")
      .def_property_readonly(
          "loop_start", [](const MinkowskiSum& s) { return ints_of(s.loop_start); },
          "(F + 1,): facet f's loop is loop_vertex[loop_start[f]:loop_start[f + 1]] (empty unless parts is WHOLE).")
      .def_property_readonly(
          "loop_vertex", [](const MinkowskiSum& s) { return ints_of(s.loop_vertex); },
          "The facets' loops back to back, counter-clockwise from outside (indices into vertices).")
      .def_readonly("V", &MinkowskiSum::V, "The number of vertices.")
      .def_readonly("E", &MinkowskiSum::E, "The number of edges.")
      .def_readonly("F", &MinkowskiSum::F, "The number of facets.")
      .def_readonly("euler_ok", &MinkowskiSum::euler_ok, "V - E + F == 2 and every edge has two facets.")
      .def_readonly("radius", &MinkowskiSum::radius, "The radius swept around the polytope (rounded operands: their radii added).")
      .def_readonly("parts", &MinkowskiSum::parts, "What it holds.")
      .def(
          "contains", [](const MinkowskiSum& s, const py::handle& p) { return contains(s, vector_of(p, "point")); }, py::arg("point"),
          "True if the point lies in the closed sum (within its radius, for a rounded one).")
      .def("__repr__", [](const MinkowskiSum& s) {
        return "<minksum.Sum: V " + std::to_string(s.V) + ", E " + std::to_string(s.E) + ", F " + std::to_string(s.F) + ">";
      });
  m.def(
      "minkowski_sum",
      [](const ConvexShape& a, const py::handle& pa, const ConvexShape& b, const py::handle& pb, SumParts parts,
         const py::handle& out) { return sum_of(&minkowski_sum, "minkowski_sum", a, pa, b, pb, parts, out); },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("parts") = SumParts::Whole, py::arg("out") = py::none(),
      sum_doc("(+)").c_str());
  m.def(
      "minkowski_difference",
      [](const ConvexShape& a, const py::handle& pa, const ConvexShape& b, const py::handle& pb, SumParts parts,
         const py::handle& out) { return sum_of(&minkowski_difference, "minkowski_difference", a, pa, b, pb, parts, out); },
      py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("parts") = SumParts::Whole, py::arg("out") = py::none(),
      (sum_doc("(-)") + "\nThe configuration-space obstacle of the placed shapes.").c_str());
}

}  // namespace minksum::python
