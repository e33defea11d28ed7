// tensormass-bench: the benchmarks, apart from the product CLI (which runs
// this program for `tensormass bench ...`). `tensormass-bench help` lists them.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "adaptive_bench.hpp"
#include "kernel_bench.hpp"
#include "paper_bench.hpp"
#include "refine_bench.hpp"
#include "runtime_bench.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/common/thread_defaults.hpp"

namespace {

constexpr const char* kUsage =
    "usage: tensormass-bench BENCHMARK [ARGS]   (also run as `tensormass bench BENCHMARK [ARGS]`)\n"
    "\n"
    "benchmarks:\n"
    "  kernels [--json FILE] [--quick]  time every kernel (median ns per element)\n"
    "  runtime [--quick] [--json FILE] [--only NAME] ...\n"
    "                                   whole solves against CalculiX, implicit steps, the quad beam\n"
    "                                   (docs/results/runtime.md)\n"
    "  paper [--quick | --smoke] [--json FILE] [--out DIR]\n"
    "                                   the origin report's Table 1 and Figure 12 (docs/results/paper.md)\n"
    "  adaptive [--quick] [--json FILE] [--only NAME]\n"
    "                                   the adaptive model against the pure laws (docs/results/adaptive.md)\n"
    "  refine [--quick] [--json FILE]   local refinement by R_ZZ against uniform refinement: 2D plate with a\n"
    "                                   probe, 3D tool indentation with law switching (docs/results/refine.md)\n"
    "  help                             this text\n";

}  // namespace

int main(int argc, char** argv) {
  tensormass::apply_default_wait_policy(argv);  // benchmarks measure what a user runs
  if (argc < 2) {
    std::fprintf(stderr, "tensormass bench: missing benchmark\n\n%s", kUsage);
    return 2;
  }
  const std::string benchmark = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    if (benchmark == "help" || benchmark == "--help" || benchmark == "-h") {
      std::fputs(kUsage, stdout);
      return 0;
    }
    if (benchmark == "kernels") return tensormass::bench::kernels_command(args);
    if (benchmark == "runtime") return tensormass::bench::runtime_command(args);
    if (benchmark == "paper") return tensormass::bench::paper_command(args);
    if (benchmark == "adaptive") return tensormass::bench::adaptive_command(args);
    if (benchmark == "refine") return tensormass::bench::refine_command(args);
  } catch (const tensormass::NumericalError& error) {
    std::fprintf(stderr, "tensormass bench: numerical failure: %s\n", error.what());
    return 3;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "tensormass bench: error: %s\n", error.what());
    return 2;
  }
  std::fprintf(stderr,
               "tensormass bench: unknown benchmark '%s' (expected kernels, runtime, paper, adaptive or refine)\n\n%s",
               benchmark.c_str(), kUsage);
  return 2;
}
