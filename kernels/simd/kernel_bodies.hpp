// The kernel table of one ISA (internal): each per-ISA translation unit includes this file with
// its own compiler flags and instantiates make_table<Arch>(); the families it fills use only the
// Simd<T, Arch> operations (lanes.hpp).
#pragma once

#include "simd/box_box.hpp"
#include "simd/box_pair.hpp"
#include "simd/box_proximity.hpp"
#include "simd/box_triangle.hpp"
#include "simd/side_masks.hpp"
#include "simd/support.hpp"
#include "simd/triangle_distance.hpp"

namespace minksum::detail {

// The table filled member by member, by name: a reordering of KernelTable cannot shift a kernel
// into another's slot, and a member left out stays null, which Kernels.EveryTableIsComplete
// rejects. (GCC's sanitizer builds refuse a function pointer's null test in a static_assert.)
template <class Arch>
constexpr KernelTable make_table() {
  KernelTable t{};
  t.box_box_f = &BoxBoxKernels<float, Arch>::box_box;
  t.box_box_d = &BoxBoxKernels<double, Arch>::box_box;
  t.box_tri_f = &BoxTriangleKernels<float, Arch>::box_triangle;
  t.box_tri_d = &BoxTriangleKernels<double, Arch>::box_triangle;
  t.support_f = &SupportKernels<float, Arch>::support;
  t.support_d = &SupportKernels<double, Arch>::support;
  t.box_box_single_d = &BoxBoxAxes<double, Arch>::box_box_axes;
  t.box_box_proximity_f = &BoxProximityKernels<float, Arch>::box_box_proximity;
  t.box_box_proximity_d = &BoxProximityKernels<double, Arch>::box_box_proximity;
  t.box_box_separation_f = &BoxSeparation<float, Arch>::box_box_separation;
  t.box_box_separation_d = &BoxSeparation<double, Arch>::box_box_separation;
  t.box_triangle_overlap_f = &BoxTriangleKernels<float, Arch>::box_triangle_overlap;
  t.box_triangle_overlap_d = &BoxTriangleKernels<double, Arch>::box_triangle_overlap;
  t.box_pair_d = &BoxPairQuery<double, Arch>::box_pair;
  t.tri_tri_f = &TriangleDistanceKernels<float, Arch>::triangle_distance;
  t.tri_tri_d = &TriangleDistanceKernels<double, Arch>::triangle_distance;
  t.side_masks_d = &SideKernels<Arch>::side_masks;
  return t;
}

}  // namespace minksum::detail
