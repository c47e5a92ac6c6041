// The kernels compiled for scalar (this file's compiler flags are set in CMakeLists.txt).
#include "simd/kernel_bodies.hpp"

namespace minksum::detail {

constexpr KernelTable kTableScalar = make_table<ScalarArch>();
static_assert(table_complete(kTableScalar), "every kernel of the table is set");

}  // namespace minksum::detail
