// Scalar double reference twins of the plane kernels: plain, per pair, brute force over the
// corners and vertices. Test support, not in the library: every ISA is checked against them.
#pragma once

#include <minksum/kernels.hpp>

namespace minksum::detail {

/// Box-box planes as the kernel lays them out, with parallel-edge threshold tau.
void box_box_reference(const Box& a, const Box& b, bool difference, double tau, KernelPlane (&out)[30]);

/// Box-triangle planes as the kernel lays them out, with parallel-edge threshold tau.
void box_triangle_reference(const Box& box, const Triangle& tri, bool difference, double tau, KernelPlane (&out)[26]);

/// Support of the box in direction n by enumerating its 8 corners (first maximiser's code).
double box_support_brute(const Box& b, const Eigen::Vector3d& n, int* code);

}  // namespace minksum::detail
