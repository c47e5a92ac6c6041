// The kernels compiled for avx2 (this file's compiler flags are set in CMakeLists.txt).
#include "kernel_bodies.hpp"

namespace minksum::detail {

KernelTable table_avx2() { return make_table<xsimd::fma3<xsimd::avx2>>(); }

}  // namespace minksum::detail
