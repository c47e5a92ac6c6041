// The kernels compiled for avx512 (this file's compiler flags are set in CMakeLists.txt).
#include "kernel_bodies.hpp"

namespace minksum::detail {

KernelTable table_avx512() { return make_table<xsimd::avx512bw>(); }

}  // namespace minksum::detail
