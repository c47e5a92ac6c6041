// minksum: object-space Minkowski sums of simple convex 3D objects. Umbrella header.
#pragma once

#include <minksum/kernels.hpp>
#include <minksum/mesh.hpp>
#include <minksum/model.hpp>
#include <minksum/query.hpp>
#include <minksum/shape.hpp>
#include <minksum/sum.hpp>
#include <minksum/version.hpp>
