/// \file paper_bench.hpp
/// `tensormass bench paper [--quick | --smoke] [--json FILE] [--out DIR]
/// [--repetitions N] [--no-3d] [--no-plots]`: the origin report's Table 1 and
/// Figure 12 on our code (docs/results/paper.md). 2D cantilever beams of
/// 60 x 10 and 30 x 10 square quads (and 3D tet, hex and mixed beams),
/// clamped at x = 0, under gravity, implicit Euler with the same settings for
/// every run: pure Hooke, pure StVK, and adaptive runs (Hooke elements
/// upgraded to StVK) under R_EL, R_V, R_S and R_NL at three thresholds each.
/// Per run: mean and median ms per step (median over repetitions), the
/// elements upgraded, and the error against the pure StVK run (largest nodal
/// distance over all steps / beam length). Also the criteria overhead (an
/// adaptive run whose threshold is never reached, against pure Hooke).
#ifndef TENSORMASS_BENCH_PAPER_BENCH_HPP
#define TENSORMASS_BENCH_PAPER_BENCH_HPP

#include <string>
#include <vector>

namespace tensormass::bench {

/// Runs the benchmark with the arguments after `bench paper`. Returns the
/// process exit code: 0 done (targets may be missed), 1 a pure run failed or
/// a file cannot be written, 2 bad arguments.
int paper_command(const std::vector<std::string>& args);

}  // namespace tensormass::bench

#endif
