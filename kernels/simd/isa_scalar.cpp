// The kernels compiled for scalar (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableScalar = make_table<ScalarArch>();

}  // namespace minksum::detail
