// Per-ISA rows of the SoA kernels, IsaKernels/<kernel>/<precision>/<isa>: a benchmark body run
// with the kernels forced to one ISA, once per ISA the CPU supports. The report's per-ISA
// table reads them; every other row runs on the best ISA.
#pragma once

#include <benchmark/benchmark.h>
#include <minksum/kernels.hpp>

#include <string>

namespace bench {

/// Registers body(state) as IsaKernels/<kernel>/<precision>/<isa> for every supported ISA.
template <class Body>
void register_per_isa(const std::string& kernel, const std::string& precision, Body body) {
  using minksum::Isa;
  for (Isa isa : {Isa::Scalar, Isa::Sse4_2, Isa::Avx2, Isa::Avx512}) {
    if (!minksum::isa_supported(isa)) continue;
    const std::string name = "IsaKernels/" + kernel + "/" + precision + "/" + minksum::to_string(isa);
    benchmark::RegisterBenchmark(name.c_str(), [isa, body](benchmark::State& state) {
      const Isa before = minksum::active_isa();
      minksum::force_isa(isa);
      body(state);
      minksum::force_isa(before);
    });
  }
}

}  // namespace bench
