// The kernels compiled for sse4_2 (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableSse4_2 = make_table<xsimd::sse4_2>();

}  // namespace minksum::detail
