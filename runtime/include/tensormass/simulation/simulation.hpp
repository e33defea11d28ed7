/// \file simulation.hpp
/// Runs a scene end to end: reads and checks everything first (a bad input
/// writes nothing), then integrates while reporting progress and writing
/// frames, and finally writes final.vtu, series.pvd and summary.json.
/// A numerical failure writes last_good.vtu and a summary with status
/// "failed" before the NumericalError propagates.
#ifndef TENSORMASS_SIMULATION_HPP
#define TENSORMASS_SIMULATION_HPP

#include <string>
#include <vector>

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/solvers/integrators.hpp"

namespace tensormass {

struct RunOptions {
  bool progress = true;  ///< progress on stderr (a bar on a terminal, lines otherwise)
  /// Continue from the output directory's checkpoint.bin (checkpoint.hpp)
  /// when there is one; start afresh when there is none.
  bool resume = false;
};

/// What a run produced, for the end-of-run summary and tests.
struct RunReport {
  std::string output_directory;
  std::vector<std::string> files;  ///< written, relative to output_directory
  State state;
  int resumed_from_step = -1;  ///< the checkpoint's step when the run was resumed, else -1
  SolveStatistics statistics;
  double wall_seconds = 0;
  double output_seconds = 0;
  /// Dynamic runs (0 for static ones): completed steps * dt.
  double simulated_seconds = 0;
  /// Dynamic runs: wall seconds of the time loop, summed over the completed
  /// steps: the integrator's step (loads, constraints, assembly, linear
  /// solves, finiteness and inversion checks) plus the adaptive model's work
  /// after it (blends, criteria, switches). Not timed: reading the mesh,
  /// building the model and solver, the explicit stable-step estimate, frame
  /// and track output, the progress display and summary.json.
  double loop_seconds = 0;
  /// simulated_seconds / loop_seconds (0 when nothing was timed).
  double real_time_factor() const { return loop_seconds > 0 ? simulated_seconds / loop_seconds : 0.0; }
  /// Tracked groups and their files (relative to output_directory), in scene order.
  std::vector<std::pair<std::string, std::string>> tracks;
  int nodes = 0, cells = 0, dofs = 0, free_dofs = 0;
  std::vector<std::pair<std::string, int>> cells_per_law;
  std::vector<std::pair<std::string, int>> cells_per_type;
  std::string linear_solver;
  double max_displacement = 0;
  int max_displacement_node = -1;
  // adaptive model (zeros and empty without `adaptivity`)
  double criteria_seconds = 0;
  std::vector<double> criterion_seconds;  ///< per scene criterion
  int switches = 0;
  std::vector<AdaptivityRecord> adaptivity;
  /// Per finished step: milliseconds in assembly, solve and criteria.
  std::vector<double> step_assembly_ms, step_solve_ms, step_criteria_ms;
};

RunReport run_scene(const Scene& scene, const RunOptions& options = {});

/// The one-screen text summary printed at the end of `tensormass run`.
std::string format_report(const Scene& scene, const RunReport& report);

}  // namespace tensormass

#endif
