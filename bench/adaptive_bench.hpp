/// \file adaptive_bench.hpp
/// `tensormass bench adaptive [--quick] [--json FILE] [--only NAME]`: does
/// the adaptive model pay? Local-deformation scenes, each run with the pure
/// linear law, the pure rich law and adaptive runs (a law ladder from the
/// linear law to the rich one) at several thresholds, all implicit with
/// default settings (threads, solver). Per run: mean ms per step and its
/// assembly, solve and criteria shares, cells per law at the end, and the
/// error against the pure rich law: the largest nodal distance over all
/// steps over the rich run's largest displacement. Targets are
/// printed beside the figures (docs/results/adaptive.md).
#ifndef TENSORMASS_BENCH_ADAPTIVE_BENCH_HPP
#define TENSORMASS_BENCH_ADAPTIVE_BENCH_HPP

#include <string>
#include <vector>

namespace tensormass::bench {

/// Runs the benchmark with the arguments after `bench adaptive`. Returns 0
/// (targets may be missed), 1 when a pure run failed or the JSON file cannot
/// be written, 2 for bad arguments.
int adaptive_command(const std::vector<std::string>& args);

}  // namespace tensormass::bench

#endif
