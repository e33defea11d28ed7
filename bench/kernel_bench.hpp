/// \file kernel_bench.hpp
/// `tensormass bench kernels [--json FILE] [--quick]`: single-thread timings
/// (median ns per element) of `gradient` and `gradient_hessian` for every
/// LES triple of the registry, side by side with a plain hand-written
/// St Venant-Kirchhoff baseline (tet4, hex8), and the performance targets.
#ifndef TENSORMASS_BENCH_KERNEL_BENCH_HPP
#define TENSORMASS_BENCH_KERNEL_BENCH_HPP

#include <string>
#include <vector>

namespace tensormass::bench {

/// Runs the benchmark with the arguments after `bench kernels`. Returns the
/// process exit code: 0 done, 1 the baseline disagrees with the generated
/// kernels (or the JSON file cannot be written), 2 bad arguments.
int kernels_command(const std::vector<std::string>& args);

}  // namespace tensormass::bench

#endif
