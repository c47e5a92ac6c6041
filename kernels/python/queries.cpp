// The convex pair's queries (minksum/query.hpp): proximity, the contact patch and the time of
// impact, with their result types. A query does not release the GIL: it takes microseconds, and
// releasing it would cost a tenth of that.

#include <minksum/query.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <algorithm>
#include <cstring>

namespace minksum::python {

namespace {

// Argument `name` as a T, or TypeError naming it and the type it takes.
template <class T>
T argument(PyObject* value, const char* name, const char* type) {
  const auto wrong = [&] {
    return py::type_error(std::string("proximity(): ") + name + " must be a " + type + ", not " + Py_TYPE(value)->tp_name);
  };
  try {
    return py::cast<T>(py::handle(value));
  } catch (const py::cast_error&) {
    throw wrong();
  } catch (const py::reference_cast_error&) {  // (None for a reference: pybind11 said RuntimeError(''))
    throw wrong();
  }
}

// proximity(a, pose_a, b, pose_b, want=Want.WITNESSES, cache=None), bound by hand as a vectorcall
// function: it is the call a loop makes once per tick, and pybind11's dispatcher copies the
// keyword arguments into a dict on every call (330 ns of the 1.1 us a coherent call took from
// Python, the query's own 0.23 us included).
PyObject* proximity_call(PyObject*, PyObject* const* args, Py_ssize_t nargs, PyObject* kwnames) {
  static const char* const names[] = {"a", "pose_a", "b", "pose_b", "want", "cache"};
  try {
    PyObject* v[6] = {nullptr, nullptr, nullptr, nullptr, nullptr, nullptr};
    if (nargs > 6) throw py::type_error("proximity() takes at most 6 arguments");
    std::copy(args, args + nargs, v);
    const Py_ssize_t nkw = kwnames ? PyTuple_GET_SIZE(kwnames) : 0;
    for (Py_ssize_t k = 0; k < nkw; ++k) {
      const char* name = PyUnicode_AsUTF8(PyTuple_GET_ITEM(kwnames, k));
      const auto slot = std::find_if(std::begin(names), std::end(names), [&](const char* n) { return name && !std::strcmp(n, name); });
      if (slot == std::end(names)) throw py::type_error(std::string("proximity() got an unexpected keyword argument '") + (name ? name : "") + "'");
      if (v[slot - names]) throw py::type_error(std::string("proximity() got multiple values for argument '") + name + "'");
      v[slot - names] = args[nargs + k];
    }
    for (int k = 0; k < 4; ++k)
      if (!v[k]) throw py::type_error(std::string("proximity() missing required argument '") + names[k] + "'");
    const ConvexShape& a = argument<const ConvexShape&>(v[0], "a", "minksum.Shape");
    const ConvexShape& b = argument<const ConvexShape&>(v[2], "b", "minksum.Shape");
    const Want want = v[4] && v[4] != Py_None ? want_of(argument<Want>(v[4], "want", "minksum.Want")) : Want::Witnesses;
    ProximityCache* cache = v[5] && v[5] != Py_None ? &argument<ProximityCache&>(v[5], "cache", "minksum.ProximityCache") : nullptr;
    const Eigen::Isometry3d pa = pose_of(v[1], "pose_a"), pb = pose_of(v[3], "pose_b");
    Proximity out;
    check(cache ? proximity(a, pa, b, pb, *cache, out, want) : proximity(a, pa, b, pb, out, want), "proximity",
          {{pa, "pose_a"}, {pb, "pose_b"}});
    not_asked(want, out);
    return py::cast(out, py::return_value_policy::move).release().ptr();
  } catch (py::error_already_set& e) {
    e.restore();
  } catch (py::builtin_exception& e) {
    e.set_error();
  } catch (const std::exception& e) {  // (bad_alloc): an exception must not leave a C function
    PyErr_SetString(PyExc_RuntimeError, e.what());
  }
  return nullptr;
}

PyMethodDef proximity_def = {
    "proximity", reinterpret_cast<PyCFunction>(reinterpret_cast<void (*)()>(&proximity_call)), METH_FASTCALL | METH_KEYWORDS,
    "proximity($module, a, pose_a, b, pose_b, want=None, cache=None)\n--\n\n"
    "The proximity of two shapes, each placed by its pose (None, a 4x4 array, or (rotation, translation)): exact\n"
    "distance and closest points, or penetration depth and direction, to the fields `want` asks for (a Want; None:\n"
    "Want.WITNESSES). Rounded shapes: their cores' answer with the radii added. With a cache (a ProximityCache), the\n"
    "query starts from the last answer's features. Returns a Proximity."};

ContactPatch patch_of(const ConvexShape& a, const py::handle& pose_a, const ConvexShape& b, const py::handle& pose_b,
                      double margin, ProximityCache* cache, bool reduce) {
  const Eigen::Isometry3d pa = pose_of(pose_a, "pose_a"), pb = pose_of(pose_b, "pose_b");
  ContactPatch out;
  check(cache ? contact_patch(a, pa, b, pb, margin, *cache, out) : contact_patch(a, pa, b, pb, margin, out), "contact_patch",
        {{pa, "pose_a"}, {pb, "pose_b"}});
  if (reduce) reduce_contact_patch(out);
  return out;
}

TimeOfImpact impact_of(const ConvexShape& a, const py::handle& a0, const py::handle& a1, const ConvexShape& b,
                       const py::handle& b0, const py::handle& b1, double tolerance) {
  const Eigen::Isometry3d pa0 = pose_of(a0, "a0"), pa1 = pose_of(a1, "a1"), pb0 = pose_of(b0, "b0"), pb1 = pose_of(b1, "b1");
  TimeOfImpact out;
  check(time_of_impact(a, pa0, pa1, b, pb0, pb1, out, tolerance), "time_of_impact",
        {{pa0, "a0"}, {pa1, "a1"}, {pb0, "b0"}, {pb1, "b1"}});
  return out;
}

py::tuple feature_of(const ContactPatch::Feature& f) {
  static const char* const kinds[] = {"none", "vertex", "edge", "face"};
  return py::make_tuple(kinds[int(f.kind)], f.index[0], f.index[1]);
}

// A read-only field that is a 3-vector, as a new (3,) array.
#define MINKSUM_VECTOR(Type, field, doc) \
  def_property_readonly(#field, [](const Type& r) { return array_of(r.field); }, doc)

void register_results(py::module_& m) {
  py::class_<Proximity>(m, "Proximity",
                        "Everything a collision or haptics caller asks of two convex objects A and B. A field the call's\n"
                        "`want` did not ask for is NaN (distance and depth below Want.DISTANCE, the points below\n"
                        "Want.WITNESSES, the farthest pair without Want.MAX_DISTANCE).")
      .def_readonly("intersecting", &Proximity::intersecting, "A and B share a point (touching counts).")
      .def_readonly("distance", &Proximity::distance, "The length of the shortest segment between A and B; 0 if intersecting.")
      .MINKSUM_VECTOR(Proximity, point_a, "Its end on A (separated), or A's deepest point.")
      .MINKSUM_VECTOR(Proximity, point_b, "Its end on B (separated), or B's deepest point.")
      .def_readonly("max_distance", &Proximity::max_distance, "The farthest pair's distance (Want.MAX_DISTANCE).")
      .MINKSUM_VECTOR(Proximity, far_a, "That pair's point on A.")
      .MINKSUM_VECTOR(Proximity, far_b, "That pair's point on B.")
      .def_readonly("penetration_depth", &Proximity::penetration_depth, "The minimum translation distance when intersecting, else 0.")
      .MINKSUM_VECTOR(Proximity, penetration_direction,
                      "Unit: moving B by penetration_depth times it makes them touch (zero when separated).")
      .def_readonly("searched", &Proximity::searched, "The answer came from the exhaustive search (statistics).")
      .def("__repr__", [](const Proximity& p) {
        return "<minksum.Proximity: intersecting " + std::string(p.intersecting ? "True" : "False") + ", distance " +
               std::string(py::repr(py::float_(p.distance))) + ", depth " + std::string(py::repr(py::float_(p.penetration_depth))) + ">";
      });
  py::class_<ProximityCache>(m, "ProximityCache",
                             "What a query keeps from one call to the next on one pair (coherence). The answer is the cold\n"
                             "query's whatever it holds. One per pair; not shared between threads.")
      .def(py::init<>(), "A cold cache.")
      .def_readonly("warm", &ProximityCache::warm, "Answers proven from the cache.")
      .def_readonly("cold", &ProximityCache::cold, "Answers computed cold.")
      .def_readonly("searched", &ProximityCache::searched, "Answers that needed the exhaustive search.");
  py::class_<ContactPatch>(m, "ContactPatch", "Where two convex shapes touch, or would within a margin.")
      .def_property_readonly(
          "points", [](const ContactPatch& p) { return array_of(p.points, p.size); },
          "The patch (k, 3) on A's supporting plane, counter-clockwise about the normal (k = 0: farther apart than the margin).")
      .MINKSUM_VECTOR(ContactPatch, normal, "Unit normal of both supporting planes, from A towards B.")
      .def_readonly("depth", &ContactPatch::depth, "The penetration depth (0 touching), or minus the distance when apart.")
      .def_property_readonly(
          "feature_a", [](const ContactPatch& p) { return feature_of(p.feature_a); },
          "A's supporting feature: (kind, index, index) with kind 'face', 'edge', 'vertex' or 'none'.")
      .def_property_readonly(
          "feature_b", [](const ContactPatch& p) { return feature_of(p.feature_b); }, "B's supporting feature.");
  py::class_<TimeOfImpact>(m, "TimeOfImpact", "When two moving shapes first come within the tolerance.")
      .def_readonly("hit", &TimeOfImpact::hit, "They come within the tolerance at some time in [0, 1].")
      .def_readonly("time", &TimeOfImpact::time, "That time (0: touching at the start; 1: no hit).")
      .def_readonly("distance", &TimeOfImpact::distance, "|point_b - point_a| then (<= tolerance).")
      .MINKSUM_VECTOR(TimeOfImpact, normal, "Unit, from A towards B: a separating plane's normal then.")
      .MINKSUM_VECTOR(TimeOfImpact, point_a, "A point on A then (world frame).")
      .MINKSUM_VECTOR(TimeOfImpact, point_b, "And on B.")
      .def_readonly("tolerance", &TimeOfImpact::tolerance, "The stopping distance used.")
      .def_readonly("converged", &TimeOfImpact::converged, "False: the advancement stopped short of the tolerance.")
      .def_readonly("iterations", &TimeOfImpact::iterations, "GJK iterations made.")
      .def_readonly("triangle", &TimeOfImpact::triangle, "Against a mesh: the triangle of the answer (else -1).");
}

}  // namespace

void register_queries(py::module_& m) {
  register_results(m);
  m.add_object("proximity", py::reinterpret_steal<py::object>(PyCFunction_NewEx(&proximity_def, m.ptr(), m.attr("__name__").ptr())));
  m.def("contact_patch", &patch_of, py::arg("a"), py::arg("pose_a"), py::arg("b"), py::arg("pose_b"), py::arg("margin") = 0.0,
        py::arg("cache") = nullptr, py::arg("reduce") = false,
        "The contact patch of two posed shapes that overlap, touch or lie within `margin`: a point, a segment or a convex\n"
        "polygon (empty farther apart). reduce=True keeps the 4 points of largest area, as contact solvers take it.");
  m.def("time_of_impact", &impact_of, py::arg("a"), py::arg("a0"), py::arg("a1"), py::arg("b"), py::arg("b0"), py::arg("b1"),
        py::arg("tolerance") = 0.0,
        "When A moving from pose a0 to a1 and B from b0 to b1 first touch (origins along segments, rotations about one\n"
        "axis at a constant rate): conservative advancement with certified bounds. tolerance 0: the scene's default.");
}

}  // namespace minksum::python
