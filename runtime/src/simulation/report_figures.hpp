// The figures of a run's report that are computed at its end: the largest
// displacement, cells per law and element type, the adaptive model's
// counters, peak memory and the time loop. Internal header.
#ifndef TENSORMASS_SIMULATION_REPORT_FIGURES_HPP
#define TENSORMASS_SIMULATION_REPORT_FIGURES_HPP

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/parallel/distribution.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass::detail {

/// report.max_displacement and its node; `state`: the whole mesh's.
void locate_max_displacement(const Model& model, const State& state, RunReport& report);
/// The adaptive model's times, switches and records (nothing without one).
void collect_adaptivity(const Adaptivity* adaptivity, RunReport& report);
/// This process's peak resident memory so far, in MiB.
double peak_memory_mib();
/// Cells per law and per element type, of the whole mesh: over MPI ranks
/// each counts its own cells, and the counts are summed (collective).
void count_cells(const Model& model, const Distribution* distribution, RunReport& report);
/// Simulated and time-loop seconds of a dynamic run (see RunReport::loop_seconds).
void time_loop(const Scene& scene, const State& state, double adaptivity_seconds, RunReport& report);

}  // namespace tensormass::detail

#endif
