/// \file runtime_bench.hpp
/// `tensormass bench runtime [--quick] [--json FILE] [--only NAME] ...`:
/// whole-solver timings (docs/results/runtime.md):
///   ccx       a static StVK cantilever of tet4 (15,000 tets; 1,500 with
///             --quick) solved by tensormass (Newton, CHOLMOD) and by
///             CalculiX (NLGEOM, same increments, tight controls) in the same
///             run: wall-clock ratio and displacement agreement;
///   implicit  linearised implicit Euler steps of StVK tet beams (~10k and
///             ~100k tets), CHOLMOD and CG: time per step split into
///             assembly, solve and the rest, and the ratio of a CG step to
///             "one assembly + N_cg sparse matrix-vector products";
///   quad      the origin report's 600-quad 2D beam under gravity, implicit
///             Euler, Hooke vs StVK on one core: ms per step and the ratio.
#ifndef TENSORMASS_BENCH_RUNTIME_BENCH_HPP
#define TENSORMASS_BENCH_RUNTIME_BENCH_HPP

#include <string>
#include <vector>

namespace tensormass::bench {

/// Runs the benchmark with the arguments after `bench runtime`. Returns the
/// process exit code: 0 done (targets may be missed; ccx missing is a skip),
/// 1 a solve failed or tensormass and CalculiX disagree beyond 1e-4 (or the
/// JSON file cannot be written), 2 bad arguments.
int runtime_command(const std::vector<std::string>& args);

}  // namespace tensormass::bench

#endif
