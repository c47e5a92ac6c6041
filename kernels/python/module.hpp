// The Python module's parts, one registration function each (module.cpp calls them in order).
#pragma once

#include <pybind11/pybind11.h>

namespace minksum::python {

/// minksum.Shape.
void register_shapes(pybind11::module_& m);
/// proximity, contact_patch, time_of_impact and their result types.
void register_queries(pybind11::module_& m);
/// minkowski_sum, minkowski_difference and minksum.Sum.
void register_sums(pybind11::module_& m);
/// minksum.Mesh, mesh_distance, mesh_contact, a tool's time of impact, and the file readers.
void register_meshes(pybind11::module_& m);

/// The batches of minksum/parallel.hpp.
void register_batches(pybind11::module_& m);

}  // namespace minksum::python
