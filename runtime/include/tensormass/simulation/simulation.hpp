/// \file simulation.hpp
/// Runs a scene, whole or step by step: reads and checks everything first
/// (a bad input writes nothing), then integrates while reporting progress
/// and writing frames, and finally writes final.vtu, series.pvd and summary.json.
/// A numerical failure writes last_good.vtu and a summary with status
/// "failed" before the NumericalError propagates.
#ifndef TENSORMASS_SIMULATION_HPP
#define TENSORMASS_SIMULATION_HPP

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/scene/scene.hpp"

namespace tensormass {

struct RunOptions {
  bool progress = true;  ///< progress on stderr (a bar on a terminal, lines otherwise)
  /// Continue from the output directory's checkpoint.bin (checkpoint.hpp)
  /// when there is one; start afresh when there is none.
  bool resume = false;
  /// Over several MPI ranks, every rank holds the whole mesh and model
  /// instead of its part (the cells it assembles): mesh(), model(),
  /// criteria() then cover every cell on every rank, as a script expects.
  bool whole_mesh_on_every_rank = false;
};

/// The mesh after a refinement event (adaptivity.refine).
struct RefinementRecord {
  int step = 0;                       ///< the (load) step it followed; 0 for the mesh the run starts with
  int cells = 0;                      ///< cells of the mesh solved on (transition triangles included)
  std::vector<int> leaves_per_level;  ///< hierarchy leaves per level, from level 0 (transition triangles not counted)
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
  int mpi_ranks = 1;                    ///< MPI ranks the run was shared among
  std::vector<double> peak_memory_mib;  ///< each rank's peak resident memory at the end (MiB)
  /// Cells each rank's model holds: all of them on every rank, or its part
  /// (its own cells and those touching its nodes) when the mesh was cut.
  std::vector<double> cells_per_rank;
  /// Each rank's peak resident memory (MiB) when a phase of the run ended:
  /// "mesh" (read), "model and assembler" (built), "shared" (cut among the
  /// ranks), "solver" (ready for the first step), "first step", "end".
  /// The first phase whose peak reaches the final one set it.
  std::vector<std::pair<std::string, std::vector<double>>> peak_memory_mib_by_phase;
  std::vector<std::pair<std::string, int>> cells_per_law;
  std::vector<std::pair<std::string, int>> cells_per_type;
  std::string linear_solver;
  double max_displacement = 0;
  int max_displacement_node = -1;
  // adaptive model (zeros and empty without `adaptivity`)
  double criteria_seconds = 0;
  std::vector<double> criterion_seconds;  ///< per scene criterion
  int switches = 0;
  AdaptivityRecords adaptivity;  ///< in bounded memory; every one is in adaptivity.jsonl
  /// Refinement (empty without adaptivity.refine): the starting mesh, then
  /// one record per change of the mesh.
  std::vector<RefinementRecord> refinement;
  /// Per finished step: milliseconds in assembly, solve and criteria.
  StepSeries<double> step_assembly_ms, step_solve_ms, step_criteria_ms;
};

class Model;
class Assembler;

/// A scene's run, one step at a time: the CLI's `run` and Python's
/// tensormass.Simulation. The constructor reads and checks everything and
/// creates the output directory (a bad input writes nothing); step()
/// advances one step (static: one load step), writing frames, tracks and
/// checkpoints as the scene asks; the step that finishes the run writes
/// final.vtu, the tracks and summary.json. Stepping to the end gives the
/// same bits as run_scene.
class Simulation {
 public:
  /// Reads the scene's mesh (scene.mesh).
  explicit Simulation(const Scene& scene, const RunOptions& options = {});
  /// A mesh given in memory (Python's from_arrays); scene.mesh names it in messages.
  Simulation(const Scene& scene, Mesh mesh, const RunOptions& options = {});
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  /// One step; false, doing nothing, once the run is finished. A numerical
  /// failure writes last_good.vtu, the tracks and a "failed" summary, then
  /// throws NumericalError; the simulation is finished after it.
  bool step();
  /// Steps to the end; returns the report.
  const RunReport& run();
  bool finished() const;
  /// The report so far (complete once finished).
  const RunReport& report() const;

  const Scene& scene() const;
  const State& state() const;
  /// The mesh and model this rank holds: over several MPI ranks, unless
  /// RunOptions::whole_mesh_on_every_rank, its part of the mesh (every node,
  /// its cells; Mesh::cell_numbers gives their whole-mesh numbers).
  const Mesh& mesh() const;
  const Model& model() const;
  /// Sets cells' laws between steps (each cell keeps its element and split);
  /// InputError naming the cell when the registry has no such kernel. The
  /// adaptive model, when on, goes on switching from the new laws. `cells`
  /// are the whole mesh's numbers; a rank holding a part sets those it holds.
  void set_law(const std::vector<int>& cells, const std::string& law);
  /// Model::hold between steps.
  void set_prescribed(const std::string& group, const std::array<double, 3>& displacement,
                      const std::array<bool, 3>& components = {true, true, true});
  /// dW/du at the current displacement (dof_count, node-major): the
  /// internal force of the body on every node. At a constrained node in
  /// static equilibrium it is the force the constraint applies (the
  /// reaction; minus it, the force on the tool or support).
  std::vector<double> internal_force() const;
  /// The adaptive criteria's last values, by name, per cell of model()
  /// (empty without `adaptivity`).
  std::vector<std::pair<std::string, std::vector<double>>> criteria() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// A whole run: Simulation(scene, options).run().
RunReport run_scene(const Scene& scene, const RunOptions& options = {});

/// The one-screen text summary printed at the end of `tensormass run`.
std::string format_report(const Scene& scene, const RunReport& report);

}  // namespace tensormass

#endif
