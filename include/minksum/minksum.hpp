// minksum: object-space Minkowski sums of simple convex 3D objects. Umbrella header.
// The structure-of-arrays batch kernels and the ISA controls are opt-in, not included here:
// #include <minksum/kernels.hpp>.
#pragma once

#include <minksum/mesh.hpp>
#include <minksum/model.hpp>
#include <minksum/query.hpp>
#include <minksum/shape.hpp>
#include <minksum/sum.hpp>
#include <minksum/version.hpp>
