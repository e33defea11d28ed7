/// \file polar_bench.hpp
/// The 3D polar rotation of the corotational kernels
/// (kernels/polar_decomposition.hpp) timed against the iteration it replaced
/// (the cube-root scale at every step, stopping at 1e-10) and against the
/// batched Newton-Schulz iteration of the batched kernels
/// (kernels/kernel_support.hpp), side by side in one process, over random
/// rotations and stretches of several sizes.
#ifndef TENSORMASS_BENCH_POLAR_BENCH_HPP
#define TENSORMASS_BENCH_POLAR_BENCH_HPP

namespace tensormass::bench {

/// Prints one row per strain size: ns per call of each iteration (median of
/// `repetitions`), their ratios and the largest differences between their
/// rotations. Returns false when two disagree by more than 1e-12.
bool print_polar_rotation_timings(int matrices, int repetitions);

}  // namespace tensormass::bench

#endif
