// The kernels compiled for avx2 (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableAvx2 = make_table<xsimd::fma3<xsimd::avx2>>();
static_assert(table_complete(kTableAvx2), "every kernel of the table is set");

}  // namespace minksum::detail
