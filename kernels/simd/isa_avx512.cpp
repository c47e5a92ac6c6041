// The kernels compiled for avx512 (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableAvx512 = make_table<xsimd::avx512bw>();

}  // namespace minksum::detail
