// The kernels compiled for avx2 (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableAvx2 = make_table<xsimd::fma3<xsimd::avx2>>();

}  // namespace minksum::detail
