// The kernels compiled for sse4_2 (this file's compiler flags are set in CMakeLists.txt).
#include "kernel_bodies.hpp"

namespace minksum::detail {

KernelTable table_sse4_2() { return make_table<xsimd::sse4_2>(); }

}  // namespace minksum::detail
