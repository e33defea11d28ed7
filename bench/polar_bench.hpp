/// \file polar_bench.hpp
/// The 3D polar rotation of the corotational kernels
/// (kernels/polar_decomposition.hpp) timed against the iteration it replaced
/// (the cube-root scale at every step, stopping at 1e-10) and against the
/// batched Newton-Schulz iteration of the batched kernels
/// (kernels/kernel_support.hpp), side by side in one process, over random
/// rotations and stretches of several sizes.
#ifndef TENSORMASS_BENCH_POLAR_BENCH_HPP
#define TENSORMASS_BENCH_POLAR_BENCH_HPP

#include <vector>

namespace tensormass::bench {

/// One strain size: ns per call of each iteration (median of the
/// repetitions) and the largest differences between their rotations.
struct PolarTiming {
  double strain = 0.0;
  double ns = 0.0;          ///< kernel::polar_rotation<3>
  double ns_before = 0.0;   ///< the cube-root scale at every step, stop 1e-10
  double ns_batched = 0.0;  ///< per matrix, kernel::kBatchWidth lanes
  double difference = 0.0, batched_difference = 0.0;
};

/// Prints one row per strain size (0.001, 0.01, 0.1, 0.3) and returns them;
/// `agree` is false when two iterations disagree by more than 1e-12.
std::vector<PolarTiming> print_polar_rotation_timings(int matrices, int repetitions, bool& agree);

}  // namespace tensormass::bench

#endif
