// The kernels compiled for sse4_2 (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableSse4_2 = make_table<xsimd::sse4_2>();
static_assert(table_complete(kTableSse4_2), "every kernel of the table is set");

}  // namespace minksum::detail
