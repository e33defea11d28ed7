/// \file checkpoint.hpp
/// The full state of a run at the end of a step, written every
/// `output.checkpoint_every` steps to `checkpoint.bin` in the output
/// directory, so that `tensormass run SCENE --resume` continues a killed run
/// and ends bit for bit where the uninterrupted run would have: the state
/// and what the integrator carries between steps, the linear solver's
/// factor, the marks of the streamed track and record files, the frame series and the statistics of the steps so
/// far. A checkpoint names the scene and the mesh it belongs to by
/// fingerprints; restoring it into another is refused.
///
/// With adaptivity it also holds every cell's law and blend, the folded
/// linear part's sums (which depend on the order of past switches) and the
/// adaptive model's counters. With refinement it holds the mesh's history
/// (replayed from the scene's mesh on resume) and the coarsening memory.
#ifndef TENSORMASS_SIMULATION_CHECKPOINT_HPP
#define TENSORMASS_SIMULATION_CHECKPOINT_HPP

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/io/streamed_file.hpp"
#include "tensormass/io/vtk_writer.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/track.hpp"

namespace tensormass {

/// The file name of a run's checkpoint inside its output directory.
inline constexpr const char* kCheckpointFile = "checkpoint.bin";

/// A track of a run: its file's mark (its rows are in the file) and the
/// displacement its rows are measured from.
struct SavedTrack {
  io::StreamMark file;
  std::array<double, 3> first_shift{};
};

/// The laws of an adaptive run: kernels named "law/split" in a table, each
/// cell's current and blended-from kernel by index (-1: none).
struct SavedLaws {
  std::vector<std::string> kernels;
  std::vector<int> current, blend_from;
  std::vector<double> blend_weight;
  bool folding = false;     ///< the assembler folds linear cells (then the next fields)
  std::vector<int> folded;  ///< per cell: the folded kernel's index, or -1
  std::vector<double> folded_blocks;
  int folded_count = 0;
  long folding_changes = 0;
  bool constants_changed = false;
  AdaptivityMemory adaptivity;
};

/// The laws, blends, folded sums and adaptive counters of a run, and back.
/// restore_laws throws InputError when the saved kernels do not exist for
/// the cells' elements or do not fit.
SavedLaws save_laws(const Model& model, const Assembler& assembler, const Adaptivity& adaptivity);
void restore_laws(const SavedLaws& saved, Model& model, const Assembler& assembler, Adaptivity& adaptivity);

/// A refining run (adaptivity.refine): the hierarchy's refine and coarsen
/// operations that changed the mesh, in order, each with its marked
/// leaf-mesh cells; the coarsening memory; the mesh events so far.
struct SavedRefinement {
  std::vector<int> coarsens;    ///< per operation: 0 refine, 1 coarsen
  std::vector<int> max_levels;  ///< per operation (refine's max_level)
  std::vector<int> offsets{0};  ///< operation k marked cells[offsets[k] .. offsets[k+1])
  std::vector<int> cells;
  std::vector<int> calm;  ///< per cell of the current mesh: calm checks in a row
  double peak = 0;        ///< the largest R_ZZ so far (dynamic runs)
  /// The run's mesh events (RefinementRecord): step, cells, leaves per level.
  std::vector<int> event_steps, event_cells, event_level_offsets{0}, event_levels;
};

struct Checkpoint {
  std::uint64_t mesh_fingerprint = 0;
  std::uint64_t scene_fingerprint = 0;
  State state;
  std::vector<double> linear_solver;  ///< LinearSolver::save_state()
  SolveStatistics statistics;         ///< counts and per-step series so far (warnings not kept)
  StepSeries<double> step_assembly_ms, step_solve_ms, step_criteria_ms;
  std::vector<SavedTrack> tracks;       ///< in output.track order
  std::vector<io::SeriesEntry> series;  ///< frames written so far
  bool adaptive = false;                ///< the run has adaptivity: `laws` holds its state
  SavedLaws laws;
  io::StreamMark adaptivity_records;  ///< the adaptive run's record file (adaptivity.jsonl)
  bool refining = false;              ///< the run has adaptivity.refine: `refinement` holds its state
  SavedRefinement refinement;
};

/// A fingerprint of what the mesh holds: dimension, rest positions, every
/// block's element and connectivity, the groups' names and nodes.
std::uint64_t mesh_fingerprint(const Mesh& mesh);
/// A fingerprint of everything in the scene that changes the computed
/// states or the outputs a resumed run appends to: materials, constraints,
/// loads, the solver (but its thread count, which changes no result, and a
/// dynamic run's `steps`, so that a finished run may be continued further),
/// the adaptivity and output.every and output.track.
std::uint64_t scene_fingerprint(const Scene& scene);

/// Writes `checkpoint` to `path` atomically (a killed write leaves the
/// previous checkpoint whole).
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);
/// Reads a checkpoint; InputError naming the file when it is not one, is
/// of another version, or is truncated.
Checkpoint read_checkpoint(const std::string& path);

}  // namespace tensormass

#endif
