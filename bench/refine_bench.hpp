/// \file refine_bench.hpp
/// `tensormass bench refine [--quick] [--json FILE]`: does local refinement
/// pay? A 2D plate with a probe: a 10 x 5 cm plate of 20 x 10
/// quad4 (E 5 kPa, nu 0.45, plane strain), the bottom fixed, a 2 cm probe
/// pressed 5 mm into the middle of the top, a static Hooke solve. Runs:
/// the coarse mesh; a mesh refined uniformly to level 2 (each cell cut in
/// 16: the reference); and adaptive runs that solve, compute R_ZZ
/// (zz_indicator.hpp), refine the cells at or above a threshold times the
/// largest indicator (max_level 2) and solve again until nothing changes.
/// Per run: cells per level, the largest displacement difference at the
/// coarse mesh's nodes against the reference over the reference's largest
/// displacement, and the solve time. Then the 3D tool indentation from a
/// coarse hex mesh, dynamic, with and without law switching
/// (refine_indentation.hpp). Targets beside the figures
/// (docs/results/refine.md).
#ifndef TENSORMASS_BENCH_REFINE_BENCH_HPP
#define TENSORMASS_BENCH_REFINE_BENCH_HPP

#include <string>
#include <vector>

namespace tensormass::bench {

/// Runs the benchmark with the arguments after `bench refine`. Returns 0
/// (targets may be missed), 1 when a solve failed (in 3D: see
/// IndentationResult::failed) or the JSON file cannot be written, 2 for bad
/// arguments.
int refine_command(const std::vector<std::string>& args);

}  // namespace tensormass::bench

#endif
