// The Python module `minksum`: the public API of include/minksum/ on NumPy arrays. Every call
// checks its arrays' shapes and dtypes (ValueError naming the argument), and a Status other than
// Ok raises minksum.Error, a ValueError carrying the status: nothing reaches the library unchecked
// and nothing crashes the interpreter.

#include <minksum/query.hpp>
#include <minksum/version.hpp>

#include "python/convert.hpp"
#include "python/module.hpp"

#include <pybind11/eval.h>

namespace py = pybind11;
using namespace minksum;

PYBIND11_MODULE(minksum, m) {
  m.doc() = "Exact Minkowski sums of convex 3D shapes by the object-space method, and the proximity queries built on them.";
  m.attr("__version__") = MINKSUM_VERSION_STRING;
  py::enum_<Status>(m, "Status", "What a failed call reports (minksum.Error.status).")
      .value("OK", Status::Ok)
      .value("NON_FINITE", Status::NonFinite)
      .value("TOO_FEW_POINTS", Status::TooFewPoints)
      .value("COLLINEAR", Status::Collinear)
      .value("INVALID_MESH", Status::InvalidMesh)
      .value("NOT_CONVEX", Status::NotConvex)
      .value("INVALID_BOX", Status::InvalidBox)
      .value("DEGENERATE_RESULT", Status::DegenerateResult)
      .value("HULL_FAILED", Status::HullFailed)
      .value("OUT_OF_RANGE", Status::OutOfRange)
      .value("INVALID_POSE", Status::InvalidPose)
      .value("INVALID_ARGUMENT", Status::InvalidArgument)
      .value("CAPACITY_EXCEEDED", Status::CapacityExceeded)
      .value("UNSUPPORTED", Status::Unsupported)
      .value("EMPTY_MESH", Status::EmptyMesh)
      .value("WORKSPACE_MISMATCH", Status::WorkspaceMismatch);
  py::enum_<Want>(m, "Want", "What a proximity call computes; each level includes the ones above it. Combine with |.")
      .value("VERDICT", Want::Verdict, "intersecting alone")
      .value("DISTANCE", Want::Distance, "and the distance, or the depth and direction")
      .value("WITNESSES", Want::Witnesses, "and the closest (or deepest) points")
      .value("PATCH", Want::Patch, "witnesses on the contact patch, steady while resting or sliding")
      .value("MAX_DISTANCE", Want::MaxDistance, "the farthest pair")
      .value("ALL", Want::All, "everything")
      .def("__or__", [](Want a, Want b) { return a | b; });
  py::enum_<SumParts>(m, "SumParts", "Which parts of a sum a call computes.")
      .value("PLANES", SumParts::Planes, "the facets' planes with a support pair each")
      .value("VERTICES", SumParts::Vertices, "and the vertices, without the loops")
      .value("WHOLE", SumParts::Whole, "planes, vertices and facet loops");
  python::error_type = PyErr_NewExceptionWithDoc("minksum.Error", "A call the library refused; .status says why.",
                                                  PyExc_ValueError, nullptr);
  m.attr("Error") = py::handle(python::error_type);
  python::register_shapes(m);
  python::register_queries(m);
  python::register_sums(m);
  python::register_meshes(m);
  python::register_batches(m);
  // The sum batches' result: a list that carries each pair's status.
  py::exec(R"(
class SumList(list):
    """A list of Sum, one per pair (a failed pair's is empty: V 0), and `status`, each pair's Status code (int32, 0: OK)."""
)", m.attr("__dict__"));
}
