#include "tensormass/simulation/simulation.hpp"

#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>
#include <span>

#include "common/phase_timer.hpp"
#include "simulation/carry_laws.hpp"
#include "simulation/discretisation.hpp"
#include "simulation/progress.hpp"
#include "simulation/report_figures.hpp"
#include "simulation/resume_checkpoint.hpp"
#include "simulation/run_refinement.hpp"
#include "simulation/run_streams.hpp"
#include "simulation/state_frames.hpp"
#include "simulation/summary_json.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/io/output_directory.hpp"
#include "tensormass/io/vtk_writer.hpp"
#include "tensormass/model/locking_warning.hpp"
#include "tensormass/parallel/mpi_world.hpp"
#include "tensormass/simulation/checkpoint.hpp"
#include "tensormass/simulation/track.hpp"

namespace tensormass {

namespace {

namespace fs = std::filesystem;
using detail::CellLaws;
using detail::Discretisation;
using detail::StartMesh;
using detail::write_state;

RefinementRecord refinement_record(int step, const detail::RunRefinement& refinement) {
  return {step, refinement.leaf_mesh().cell_count(), refinement.leaves_per_level()};
}

}  // namespace

struct Simulation::Impl {
  Impl(const Scene& scene_in, StartMesh start, const RunOptions& options);
  bool observe(const State& state);
  bool refine_load_step(const State& now);
  void apply_refinement();
  void replay_refinement(const Checkpoint& checkpoint);
  void restore_refinement(const SavedRefinement& saved);
  SavedRefinement save_refinement() const;
  void restore(const Checkpoint& checkpoint);
  void refuse_what_viscous_cells_lack() const;
  void write_checkpoint_now(const State& state);
  void stream_adaptivity_record();
  std::string output_path(const std::string& name) const { return (fs::path(scene.output.directory) / name).string(); }
  bool step();
  [[noreturn]] void fail(const NumericalError& failure);
  [[noreturn]] void fail_output(const OutputError& failure);
  void finish_run();
  void close_report(const State& end, const std::string& failure);
  void share_among_ranks();
  /// The locking warnings of the model (locking_warning.hpp), in the report
  /// and, unless quiet, on stderr.
  void warn_of_locking(const RunOptions& options) {
    for (const std::string& warning : locking_warnings(disc->model, scene.model)) {
      if (options.progress && writes_files()) std::fprintf(stderr, "tensormass: warning: %s\n", warning.c_str());
      report.statistics.warnings.push_back(warning);
    }
  }
  /// Whether this process writes the files: the only one, or rank 0 of several.
  bool writes_files() const { return !distribution || distribution->rank() == 0; }
  /// Whether this rank's model holds only its part of the mesh (read_start_mesh).
  bool holds_part() const { return disc->distribution && disc->distribution->holds_part(); }
  /// Whether each rank computes only its own rows of the state (Distribution::divides_state).
  bool divides_state() const { return distribution && distribution->divides_state(); }
  /// A divided state made whole on every rank (collective): each rank's own rows, summed.
  State whole_state(const State& divided) const {
    State whole = divided;
    const std::size_t dofs = static_cast<std::size_t>(disc->model.dof_count());
    for (std::vector<double>* v :
         {&whole.displacement, &whole.velocity, &whole.previous_displacement, &whole.earlier_displacement})
      if (v->size() == dofs) *v = distribution->whole_dofs(*v);
    if (whole.warm_start.size() == static_cast<std::size_t>(disc->model.free_dof_count()))
      whole.warm_start = distribution->whole_free(whole.warm_start);
    return whole;
  }
  /// This rank's part of a whole state (a checkpoint's), the inverse of whole_state.
  State divided_state(const State& whole) const {
    State divided = whole;
    const std::size_t dofs = static_cast<std::size_t>(disc->model.dim()) * distribution->whole_node_count();
    for (std::vector<double>* v :
         {&divided.displacement, &divided.velocity, &divided.previous_displacement, &divided.earlier_displacement})
      if (v->size() == dofs) *v = distribution->local_dofs(*v);
    if (divided.warm_start.size() == static_cast<std::size_t>(distribution->global_row_count()))
      divided.warm_start = distribution->local_free(divided.warm_start);
    return divided;
  }
  /// A divided state's tracks: the tracked nodes' displacements gathered to
  /// rank 0 each step (tracked_rows: per tracked node, its local node if
  /// this rank owns it, else -1) into `tracked`, rank 0's whole-length
  /// displacement of which only the tracked nodes' entries are kept.
  std::vector<int> tracked_nodes, tracked_rows;
  std::vector<double> tracked;
  bool tracked_nodes_known = false;
  void gather_tracked_nodes();
  const std::vector<double>& tracked_displacement(const State& now);
  /// A row of every track at `now` (collective on every rank of a divided state).
  void record_tracks(const State& now) {
    if (scene.output.track.empty()) return;
    const std::vector<double>& displacement = divides_state() ? tracked_displacement(now) : now.displacement;
    for (std::size_t t = 0; t < tracks.size(); ++t) {
      const TrackRow row = tracks[t].record(now.time, displacement);
      if (streams) streams->append_track_row(t, row);
    }
  }
  /// The report's nodes, cells and dofs: the whole mesh's.
  void count_whole_mesh() {
    report.nodes = disc->whole_node_count();
    report.cells = disc->whole_cell_count();
    report.dofs = disc->model.dim() * report.nodes;
    report.free_dofs = disc->whole_free_dof_count();
  }

  /// Per cell, its level when refinement is on (empty otherwise).
  std::span<const int> levels() const { return refinement ? refinement->levels() : std::span<const int>(); }

  const std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  Scene scene;
  RunReport report;
  /// This rank's peak memory at the end of each phase so far (RunReport::peak_memory_mib_by_phase);
  /// initialised before disc: the mesh is read, the model not built yet.
  std::vector<std::pair<std::string, double>> memory_marks{{"mesh", detail::peak_memory_mib()}};
  std::unique_ptr<Discretisation> disc;
  std::unique_ptr<detail::RunRefinement> refinement;  // null without adaptivity.refine
  const Distribution* distribution = nullptr;         // disc's, once shared among ranks; null on one process
  bool dynamic;
  std::unique_ptr<Adaptivity> adaptivity;
  std::vector<GroupTrack> tracks;
  std::optional<detail::RunStreams> streams;  // rank 0's track and record files
  long streamed_evaluations = 0;              // adaptive evaluations written to the record file
  std::string checkpoint_path;
  std::unique_ptr<io::OutputDirectoryLock> output_lock;  // rank 0's, from before the checkpoint is read to the end
  Checkpoint fingerprints;                               // this run's; a checkpoint written starts from them
  State state, last_good;
  std::vector<io::SeriesEntry> series;
  detail::Progress progress;
  std::array<double, 3> phase_marks{};  // assembly, solve, criteria seconds at the last step
  std::size_t counted_steps = 0;
  void mark_memory(const char* phase) { memory_marks.emplace_back(phase, detail::peak_memory_mib()); }
  double stepping_ms = 0;
  double adaptivity_seconds = 0;  // the adaptive model's share of the time loop
  int resolves = 0;               // static: repeats of the current load step after switches
  static constexpr int kMaxResolves = 20;
  // Refinement: the transfers from the mesh of the last step to the refined
  // one, applied once the integrator has returned; a static load step is
  // then solved again (`resolve`), its time and iterations carried over.
  std::vector<LeafTransfer> pending;
  bool resolve = false;
  int refinement_passes = 0;  // static: re-solves of the current load step after refinements
  static constexpr int kMaxRefinementPasses = 10;
  double carried_ms = 0;
  int carried_iterations = 0;
  /// set_prescribed's holds, in order: applied again to a rebuilt model.
  struct Hold {
    std::string group;
    std::array<double, 3> displacement;
    std::array<bool, 3> components;
  };
  std::vector<Hold> holds;
  bool done = false;
};

/// Mesh, model and solver, the resumed checkpoint or the first evaluation
/// of the adaptive model, the output directory.
Simulation::Impl::Impl(const Scene& scene_in, StartMesh start, const RunOptions& options)
    : scene(scene_in),
      disc(std::make_unique<Discretisation>(detail::checked_mesh(scene, start), scene, report.statistics,
                                            std::move(start.cut))),
      refinement(scene.refinement.enabled ? std::make_unique<detail::RunRefinement>(scene.refinement, disc->mesh)
                                          : nullptr),
      dynamic(scene.solver.is_dynamic()),
      tracks(holds_part() ? std::move(start.tracks) : detail::make_tracks(scene, disc->mesh)),
      checkpoint_path((fs::path(scene.output.directory) / kCheckpointFile).string()),
      progress(scene.solver.total_steps(), std::string(solver_type_name(scene.solver.type)),
               options.progress && parallel::world_rank() == 0) {
  mark_memory("model and assembler");
  // The scene's mesh, before any refinement.
  fingerprints.mesh_fingerprint = holds_part() ? start.fingerprint : mesh_fingerprint(disc->mesh);
  fingerprints.scene_fingerprint = scene_fingerprint(scene);
  if (parallel::world_rank() == 0) output_lock = std::make_unique<io::OutputDirectoryLock>(scene.output.directory);
  std::optional<Checkpoint> checkpoint;
  if (options.resume) checkpoint = detail::matching_checkpoint(checkpoint_path, scene, fingerprints);
  if (checkpoint && refinement) replay_refinement(*checkpoint);
  if (parallel::world_size() > 1) share_among_ranks();
  mark_memory("shared");
  refuse_what_viscous_cells_lack();
  disc->prepare(scene);
  if (scene.adaptivity.enabled) {
    AdaptivitySettings settings = scene.adaptivity;
    if (!dynamic) settings.blend_steps = 0;  // a static solve has no steps to blend over
    adaptivity = std::make_unique<Adaptivity>(settings, disc->model, disc->assembler);
    adaptivity->distribute(distribution);
  }
  if (checkpoint)
    detail::check_checkpoint_state(*checkpoint, checkpoint_path,
                                   static_cast<std::size_t>(disc->model.dim()) * disc->whole_node_count());
  if (checkpoint && divides_state()) checkpoint->state = divided_state(checkpoint->state);
  mark_memory("solver");

  report.output_directory = scene.output.directory;
  report.mpi_ranks = distribution ? distribution->size() : 1;
  count_whole_mesh();
  report.linear_solver = scene.solver.type == SolverType::explicit_euler ? "none (lumped mass)" : disc->linear->name();
  std::error_code error;
  fs::create_directories(scene.output.directory, error);
  if (error) throw InputError("cannot create output directory " + scene.output.directory + ": " + error.message());

  state.displacement.assign(disc->model.dof_count(), 0.0);
  state.velocity.assign(disc->model.dof_count(), 0.0);
  last_good = state;
  warn_of_locking(options);
  if (checkpoint) restore(*checkpoint);
  if (writes_files())  // after every check of the checkpoint
    streams.emplace(scene.output.directory, tracks, adaptivity != nullptr, checkpoint ? &*checkpoint : nullptr,
                    checkpoint_path);
  if (checkpoint) {
    if (writes_files())
      std::fprintf(stderr, "tensormass: resuming from %s at step %d (t = %g)\n", checkpoint_path.c_str(), state.step,
                   state.time);
    return;
  }
  if (adaptivity) {
    detail::PhaseTimer timer(adaptivity_seconds);
    adaptivity->start(last_good.displacement);
    stream_adaptivity_record();
  }
  record_tracks(state);
  if (refinement) report.refinement.push_back(refinement_record(0, *refinement));
}

/// The viscous history (assembly/viscous_part.hpp) stays with the cells it
/// was built on: law switches, refinement and MPI parts do not carry it yet.
void Simulation::Impl::refuse_what_viscous_cells_lack() const {
  if (disc->assembler.viscous_part().empty()) return;
  const auto refuse = [&](const std::string& what) {
    throw InputError(scene.path + ": a viscoelastic law (one with a Prony series) does not run " + what +
                     " yet (docs/laws.md, Viscoelasticity)");
  };
  if (scene.adaptivity.enabled) refuse("with the adaptive model");
  if (refinement) refuse("with refinement");
  if (parallel::world_size() > 1) refuse("over MPI ranks");
}

/// Appends the adaptive model's latest evaluation to its record file, once.
void Simulation::Impl::stream_adaptivity_record() {
  const long evaluations = adaptivity->records().evaluations;
  if (evaluations == streamed_evaluations) return;
  if (streams) streams->append_record(adaptivity->last_record());
  streamed_evaluations = evaluations;
}

/// A resumed refining run: the mesh of the checkpoint, by replaying its
/// history from the scene's mesh.
void Simulation::Impl::replay_refinement(const Checkpoint& checkpoint) {
  if (!checkpoint.refining) return;  // the scene fingerprint covers adaptivity.refine: not reached
  refinement->restore(checkpoint.refinement);
  disc = std::make_unique<Discretisation>(refinement->leaf_mesh(), scene, report.statistics);
}

/// Every rank holds the whole model and state; each assembles the cells
/// of its part of the mesh (and those touching its nodes; the assembler
/// was built for them), evaluates the criteria of its own cells, and the
/// linear solver spreads its rows over the ranks. Rank 0 writes the files.
void Simulation::Impl::share_among_ranks() {
  distribution = disc->distribution.get();
  if (scene.solver.type != SolverType::explicit_euler) disc->linear->distribute(*distribution);
  if (adaptivity) adaptivity->distribute(distribution);  // a refinement's new cut
}

/// Everything the steps so far left behind, as the killed run had it.
void Simulation::Impl::restore(const Checkpoint& checkpoint) {
  SolveStatistics& statistics = report.statistics;
  state = checkpoint.state;
  last_good = state;
  const std::size_t history = disc->assembler.viscous_part().history_size();
  if (!state.viscous_history.empty() && state.viscous_history.size() != history)
    throw InputError("checkpoint " + checkpoint_path + ": state.viscous_history holds " +
                     std::to_string(state.viscous_history.size()) + " doubles; this scene's viscoelastic cells carry " +
                     std::to_string(history));
  if (adaptivity && !checkpoint.adaptive)
    throw InputError("checkpoint " + checkpoint_path + " holds no adaptive model's state");
  if (adaptivity) restore_laws(checkpoint.laws, disc->model, disc->assembler, *adaptivity);
  if (adaptivity) streamed_evaluations = adaptivity->records().evaluations;
  disc->linear->restore_state(checkpoint.linear_solver, disc->assembler.pattern());
  std::vector<std::string> warnings = std::move(statistics.warnings);  // this run's, not the checkpoint's
  statistics = checkpoint.statistics;
  statistics.warnings = std::move(warnings);
  report.step_assembly_ms = checkpoint.step_assembly_ms;
  report.step_solve_ms = checkpoint.step_solve_ms;
  report.step_criteria_ms = checkpoint.step_criteria_ms;
  for (std::size_t t = 0; t < tracks.size() && t < checkpoint.tracks.size(); ++t)
    tracks[t].restore(checkpoint.tracks[t].first_shift);
  series = checkpoint.series;
  counted_steps = statistics.step_ms.size();
  stepping_ms = statistics.step_ms.sum();
  phase_marks = {statistics.assembly_seconds, statistics.solve_seconds, 0.0};
  report.resumed_from_step = state.step;
  if (refinement) restore_refinement(checkpoint.refinement);
}

/// The mesh events of a resumed refining run; a dynamic run then adapts the
/// mesh as the killed run did right after writing the checkpoint.
void Simulation::Impl::restore_refinement(const SavedRefinement& saved) {
  report.refinement.clear();
  for (std::size_t e = 0; e < saved.event_steps.size(); ++e)
    report.refinement.push_back({saved.event_steps[e], saved.event_cells[e],
                                 std::vector<int>(saved.event_levels.begin() + saved.event_level_offsets[e],
                                                  saved.event_levels.begin() + saved.event_level_offsets[e + 1])});
  if (!dynamic || state.step % scene.refinement.every != 0) return;
  {
    detail::PhaseTimer timer(adaptivity_seconds);
    pending = refinement->adapt(disc->model, state.displacement);
  }
  if (!pending.empty()) apply_refinement();
}

SavedRefinement Simulation::Impl::save_refinement() const {
  SavedRefinement saved = refinement->save();
  for (const RefinementRecord& event : report.refinement) {
    saved.event_steps.push_back(event.step);
    saved.event_cells.push_back(event.cells);
    saved.event_levels.insert(saved.event_levels.end(), event.leaves_per_level.begin(), event.leaves_per_level.end());
    saved.event_level_offsets.push_back(static_cast<int>(saved.event_levels.size()));
  }
  return saved;
}

void Simulation::Impl::write_checkpoint_now(const State& state_now) {
  if (adaptivity) adaptivity->share_values();                        // on every rank: rank 0 saves all cells' values
  State whole = divides_state() ? whole_state(state_now) : State{};  // on every rank: collective
  if (!writes_files()) return;
  detail::PhaseTimer timer(report.output_seconds);
  Checkpoint saved = fingerprints;
  saved.state = divides_state() ? std::move(whole) : state_now;
  saved.linear_solver = disc->linear->save_state();
  saved.statistics = report.statistics;
  saved.step_assembly_ms = report.step_assembly_ms;
  saved.step_solve_ms = report.step_solve_ms;
  saved.step_criteria_ms = report.step_criteria_ms;
  saved.series = series;
  saved.statistics.warnings.clear();
  const std::vector<io::StreamMark> marks = streams->track_marks();
  for (std::size_t t = 0; t < tracks.size(); ++t) saved.tracks.push_back({marks[t], tracks[t].first_shift()});
  if (adaptivity) {
    saved.adaptive = true, saved.laws = save_laws(disc->model, disc->assembler, *adaptivity);
    saved.adaptivity_records = streams->record_mark();
  }
  if (refinement) saved.refining = true, saved.refinement = save_refinement();
  write_checkpoint(checkpoint_path, saved);
}

/// Which nodes rank 0's tracks read (made from the whole mesh) and which of
/// them this rank owns: collective, once.
void Simulation::Impl::gather_tracked_nodes() {
  if (writes_files())
    for (const GroupTrack& track : tracks)
      tracked_nodes.insert(tracked_nodes.end(), track.nodes().begin(), track.nodes().end());
  std::sort(tracked_nodes.begin(), tracked_nodes.end());
  tracked_nodes.erase(std::unique(tracked_nodes.begin(), tracked_nodes.end()), tracked_nodes.end());
  int count = static_cast<int>(tracked_nodes.size());
  parallel::broadcast_from_root(std::span<int>(&count, 1));
  tracked_nodes.resize(static_cast<std::size_t>(count));
  parallel::broadcast_from_root(tracked_nodes);
  const std::vector<int>& global = distribution->global_nodes();
  for (int node : tracked_nodes) {
    const auto found = std::lower_bound(global.begin(), global.end(), node);
    const int local = found != global.end() && *found == node ? static_cast<int>(found - global.begin()) : -1;
    tracked_rows.push_back(local >= 0 && distribution->owns_node(local) ? local : -1);
  }
  if (writes_files())
    tracked.assign(static_cast<std::size_t>(disc->model.dim()) * distribution->whole_node_count(), 0.0);
  tracked_nodes_known = true;
}

/// The displacement rank 0's tracks read, with only the tracked nodes'
/// entries set (collective: a sum over the ranks of those entries only).
const std::vector<double>& Simulation::Impl::tracked_displacement(const State& now) {
  if (!tracked_nodes_known) gather_tracked_nodes();
  const std::size_t d = static_cast<std::size_t>(disc->model.dim());
  std::vector<double> values(d * tracked_nodes.size(), 0.0);
  for (std::size_t k = 0; k < tracked_rows.size(); ++k)
    if (const int local = tracked_rows[k]; local >= 0)
      std::copy_n(now.displacement.begin() + static_cast<std::ptrdiff_t>(d * local), d, values.begin() + d * k);
  parallel::sum_over_ranks(values);
  for (std::size_t k = 0; k < tracked_nodes.size() && writes_files(); ++k)
    std::copy_n(values.begin() + d * k, d, tracked.begin() + static_cast<std::ptrdiff_t>(d * tracked_nodes[k]));
  return tracked;
}

/// After each finished step: the adaptive model (a static load step is
/// solved again when it switched laws: returns true), tracks, per-step
/// phase times, frames, checkpoints and progress.
bool Simulation::Impl::observe(const State& now) {
  SolveStatistics& statistics = report.statistics;
  if (carried_ms > 0 || carried_iterations > 0) {  // the solves of this load step before a refinement
    statistics.step_ms.set_back(statistics.step_ms.back() + carried_ms);
    statistics.newton_per_step.set_back(statistics.newton_per_step.back() + carried_iterations);
    carried_ms = 0, carried_iterations = 0;
  }
  if (refinement && !dynamic && refine_load_step(now)) return false;  // solved again on the refined mesh
  if (adaptivity) {
    int switches = 0;
    {
      detail::PhaseTimer timer(adaptivity_seconds);
      if (dynamic) adaptivity->advance_blends();
      switches = adaptivity->update(now.displacement, now.step);
      stream_adaptivity_record();
    }
    if (!dynamic && switches > 0 && resolves < kMaxResolves) {
      ++resolves;
      return true;  // solve this load step again with the new laws
    }
    if (!dynamic && switches > 0)
      statistics.warnings.push_back("load step " + std::to_string(now.step) + ": laws still switching after " +
                                    std::to_string(kMaxResolves) + " re-solves");
  }
  resolves = 0;
  refinement_passes = 0;
  last_good = now;
  if (memory_marks.back().first == "solver") mark_memory("first step");  // once, after the first step
  if (!scene.output.track.empty()) {
    detail::PhaseTimer timer(report.output_seconds);
    record_tracks(now);
  }
  // Per-step phase times, from the running totals.
  const double criteria_now = adaptivity ? adaptivity->criteria_seconds() : 0.0;
  report.step_assembly_ms.push_back(1e3 * (statistics.assembly_seconds - phase_marks[0]));
  report.step_solve_ms.push_back(1e3 * (statistics.solve_seconds - phase_marks[1]));
  report.step_criteria_ms.push_back(1e3 * (criteria_now - phase_marks[2]));
  phase_marks = {statistics.assembly_seconds, statistics.solve_seconds, criteria_now};
  if (scene.output.every > 0 && now.step % scene.output.every == 0) {
    detail::PhaseTimer timer(report.output_seconds);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%06d", now.step);
    const std::string file =
        write_state(scene.output.directory, name, disc->model, now, levels(), adaptivity.get(), distribution);
    series.push_back({now.time, file});
    if (writes_files()) io::write_pvd(output_path("series.pvd"), series);
  }
  // The finished steps and their time (a repeated static step is taken
  // back before it is ever counted here).
  counted_steps = statistics.step_ms.size();
  stepping_ms = statistics.step_ms.sum();
  const int every = scene.output.checkpoint_every;
  if (every > 0 && now.step % every == 0) write_checkpoint_now(now);
  progress.update(now.step, counted_steps ? stepping_ms / counted_steps : 0.0);
  if (refinement && dynamic && now.step % scene.refinement.every == 0) {
    detail::PhaseTimer timer(adaptivity_seconds);
    pending = refinement->adapt(disc->model, now.displacement);
  }
  return false;
}

/// Static: refines after a converged load step; true when the mesh changed
/// (the step is then solved again on it, see apply_refinement).
bool Simulation::Impl::refine_load_step(const State& now) {
  if (refinement_passes >= kMaxRefinementPasses) {
    if (refinement_passes == kMaxRefinementPasses)  // once, although law switches may solve the step again
      report.statistics.warnings.push_back("load step " + std::to_string(now.step) + ": mesh still refining after " +
                                           std::to_string(kMaxRefinementPasses) + " re-solves");
    refinement_passes = kMaxRefinementPasses + 1;
    return false;
  }
  {
    detail::PhaseTimer timer(adaptivity_seconds);
    pending = refinement->refine(disc->model, now.displacement);
  }
  if (pending.empty()) return false;
  ++refinement_passes;
  return true;
}

/// Carries the state to the refined mesh and builds everything on it again;
/// a static load step is then solved again from the carried displacement.
void Simulation::Impl::apply_refinement() {
  const int d = disc->model.dim();
  if (adaptivity) adaptivity->share_values();  // the new cut gives cells to other ranks
  for (const LeafTransfer& transfer : pending) {
    state.displacement = transfer_nodal_field(transfer, state.displacement, d);
    state.velocity = transfer_nodal_field(transfer, state.velocity, d);
  }
  const std::vector<int> origin = detail::cell_origins(pending);
  const CellLaws laws = detail::cell_laws(disc->model);
  pending.clear();
  // The histories the solvers extrapolate from belong to the old mesh.
  state.warm_start.clear();
  state.previous_displacement.clear();
  state.earlier_displacement.clear();
  disc = std::make_unique<Discretisation>(refinement->leaf_mesh(), scene, report.statistics);
  // Every rank refined alike (the state is the same bits everywhere): the new mesh is cut again.
  if (distribution) share_among_ranks();
  for (const Hold& hold : holds) disc->model.hold(hold.group, hold.displacement, hold.components);
  // Each new cell takes the law (and blend) of the cell it comes from,
  // before the new assembler's first assembly folds the linear-law cells.
  if (const int missed = detail::carry_laws(laws, origin, disc->model); missed > 0)
    report.statistics.warnings.push_back("step " + std::to_string(state.step) + ": " + std::to_string(missed) +
                                         " refined cells have no kernel for their parent's law and keep their "
                                         "material's law");
  if (adaptivity) adaptivity->follow(disc->model, disc->assembler, origin);
  disc->prepare(scene);
  report.refinement.push_back(refinement_record(state.step, *refinement));
  resolve = !dynamic;
  if (resolve) {  // the load step again: its solves so far count with the next one
    SolveStatistics& statistics = report.statistics;
    carried_ms += statistics.step_ms.back();
    carried_iterations += statistics.newton_per_step.back();
    statistics.step_ms.pop_back();
    statistics.newton_per_step.pop_back();
    state.step -= 1;
    state.time = static_cast<double>(state.step) / scene.solver.load_steps;
  }
  last_good = state;
}

/// One step, and the end of the run when it was the last (or when a
/// resumed run had none left). Returns whether a step was taken.
bool Simulation::Impl::step() {
  if (done) return false;
  bool stepped = false;
  try {
    if (!disc->stepper().finished(state)) {
      do {
        resolve = false;
        disc->stepper().step(state, [this](const State& now) { return observe(now); });
        if (!pending.empty()) apply_refinement();  // a new discretisation, a new integrator
      } while (resolve);
      stepped = true;
    }
    if (!disc->stepper().finished(state)) return true;
    disc->stepper().finish(state);
  } catch (const NumericalError& failure) {
    fail(failure);
  } catch (const OutputError& failure) {
    fail_output(failure);
  }
  try {
    finish_run();
  } catch (const OutputError& failure) {
    fail_output(failure);
  }
  return stepped;
}

void Simulation::Impl::fail(const NumericalError& failure) {
  done = true;
  progress.finish();
  const std::string file = write_state(scene.output.directory, "last_good", disc->model, last_good, levels(),
                                       adaptivity.get(), distribution);
  report.files.push_back(file);
  close_report(last_good, failure.what());
  throw NumericalError(std::string(failure.what()) + "; last good state (step " + std::to_string(last_good.step) +
                       ") written to " + output_path(file));
}

/// A failed write: the run stops, and summary.json says why when it can
/// be written (on one process: over MPI ranks every rank ends at once).
void Simulation::Impl::fail_output(const OutputError& failure) {
  done = true;
  progress.finish();
  if (parallel::world_size() == 1) {
    try {
      close_report(last_good, std::string("output failure: ") + failure.what());
    } catch (const std::exception&) {  // the disk is still full: the error is reported all the same
    }
  }
  output_lock.reset();
  throw OutputError(std::string(failure.what()) + "; the files written before it are whole (output " +
                    scene.output.directory + ")");
}

/// final.vtu, series.pvd, the tracks and summary.json.
void Simulation::Impl::finish_run() {
  done = true;
  progress.finish();
  {
    detail::PhaseTimer timer(report.output_seconds);
    report.files.push_back(
        write_state(scene.output.directory, "final", disc->model, state, levels(), adaptivity.get(), distribution));
  }
  if (!series.empty()) report.files.push_back("series.pvd");
  close_report(state, "");
}

/// The tracks, the report of a run that ended at `end` (failed when
/// `failure` is not empty) and summary.json.
void Simulation::Impl::close_report(const State& end, const std::string& failure) {
  if (streams) {
    detail::PhaseTimer timer(report.output_seconds);
    streams->finish(tracks, report);
  }
  if (failure.empty()) report.files.push_back("summary.json");
  report.state = divides_state() ? whole_state(end) : end;
  detail::time_loop(scene, end, adaptivity_seconds, report);
  detail::count_cells(disc->model, distribution, report);
  count_whole_mesh();
  detail::collect_adaptivity(adaptivity.get(), report);
  detail::locate_max_displacement(disc->model, report.state, report);
  if (scene.solver.type != SolverType::explicit_euler)
    report.linear_solver = disc->linear->name();  // after any fallback
  report.cells_per_rank = parallel::gather_to_root(disc->mesh.cell_count());
  report.peak_memory_mib = parallel::gather_to_root(detail::peak_memory_mib());
  report.peak_memory_mib_by_phase.clear();
  for (const auto& [phase, mib] : memory_marks)  // the same phases on every rank: collective
    report.peak_memory_mib_by_phase.emplace_back(phase, parallel::gather_to_root(mib));
  report.peak_memory_mib_by_phase.emplace_back("end", report.peak_memory_mib);
  report.wall_seconds = detail::seconds_since(start);
  if (writes_files()) detail::write_summary(output_path("summary.json"), scene, disc->model, report, failure);
  output_lock.reset();  // the run has written everything: another may take the directory
}

namespace {

/// The scene's mesh, read and checked, with the thread count set before
/// anything runs in parallel.
StartMesh read_scene_mesh(const Scene& scene, const RunOptions& options) {
  StartMesh start = detail::read_start_mesh(scene, options);
  if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
  return start;
}

}  // namespace

Simulation::Simulation(const Scene& scene, const RunOptions& options)
    : impl_(std::make_unique<Impl>(scene, read_scene_mesh(scene, options), options)) {}

Simulation::Simulation(const Scene& scene, Mesh mesh, const RunOptions& options) {
  mesh.validate();
  if (scene.solver.threads > 0) omp_set_num_threads(scene.solver.threads);
  impl_ = std::make_unique<Impl>(scene, detail::whole_start_mesh(std::move(mesh)), options);
}

Simulation::~Simulation() = default;

bool Simulation::step() { return impl_->step(); }

const RunReport& Simulation::run() {
  while (impl_->step()) {
  }
  return impl_->report;
}

bool Simulation::finished() const { return impl_->done; }
const RunReport& Simulation::report() const { return impl_->report; }
const Scene& Simulation::scene() const { return impl_->scene; }
const State& Simulation::state() const { return impl_->state; }
const Mesh& Simulation::mesh() const { return impl_->disc->mesh; }
const Model& Simulation::model() const { return impl_->disc->model; }

void Simulation::set_law(const std::vector<int>& cells, const std::string& law) {
  // `cells` number the whole mesh's cells; a rank holding part of it sets those it holds.
  const Discretisation& disc = *impl_->disc;
  Model& model = impl_->disc->model;
  const int whole = disc.whole_cell_count();
  if (!disc.assembler.viscous_part().empty())
    throw InputError("set_law: the model has viscoelastic cells, whose history does not follow a law switch yet");
  std::vector<int> held;
  for (int cell : cells) {  // all checked before any changes
    if (cell < 0 || cell >= whole)
      throw InputError("set_law: cell " + std::to_string(cell) + " is not in 0.." + std::to_string(whole - 1));
    const int local = impl_->holds_part() ? disc.distribution->local_cell(cell) : cell;
    if (local < 0) continue;
    if (!model.law_kernel(local, law))
      throw InputError("set_law: no kernel for law '" + law + "' on " + model.mesh().describe_cell(local));
    held.push_back(local);
  }
  for (int cell : held) model.set_law(cell, law);
}

void Simulation::set_prescribed(const std::string& group, const std::array<double, 3>& displacement,
                                const std::array<bool, 3>& components) {
  impl_->disc->model.hold(group, displacement, components);
  if (impl_->refinement) impl_->holds.push_back({group, displacement, components});
}

std::vector<double> Simulation::internal_force() const {
  std::vector<double> force(impl_->disc->model.dof_count(), 0.0);
  impl_->disc->assembler.assemble(impl_->state.displacement, force, nullptr);
  return force;
}

std::vector<std::pair<std::string, std::vector<double>>> Simulation::criteria() const {
  std::vector<std::pair<std::string, std::vector<double>>> out;
  if (!impl_->adaptivity) return out;
  const auto& names = impl_->adaptivity->criterion_names();
  for (std::size_t i = 0; i < names.size(); ++i)
    out.emplace_back(names[i], impl_->adaptivity->criterion_values(static_cast<int>(i)));
  return out;
}

RunReport run_scene(const Scene& scene, const RunOptions& options) {
  Simulation simulation(scene, options);
  return simulation.run();
}

}  // namespace tensormass
