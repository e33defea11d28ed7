#include "simulation/resume_checkpoint.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

namespace {

namespace fs = std::filesystem;

/// The time a run's state has after `step` steps: the load factor of a
/// static solve, step dt of a dynamic one.
double time_of_step(const SolverSettings& solver, int step) {
  return solver.is_static() ? static_cast<double>(step) / solver.load_steps : step * solver.dt;
}

/// Whether `time` is the time of `step` (a dynamic run sums dt step by step).
bool is_time_of_step(double time, const SolverSettings& solver, int step) {
  const double expected = time_of_step(solver, step);
  return std::abs(time - expected) <= 1e-8 * std::max(1.0, std::abs(expected));
}

/// InputError naming the field unless the checkpoint's step, time and
/// frames are those this scene's run writes.
void check_against_run(const Checkpoint& checkpoint, const std::string& path, const Scene& scene) {
  const auto refuse = [&](const std::string& what) {
    throw InputError("checkpoint " + path + ": " + what + " (damaged or forged; remove it to start afresh)");
  };
  const State& state = checkpoint.state;
  const SolverSettings& solver = scene.solver;
  if (state.step > solver.total_steps())
    refuse("state.step " + std::to_string(state.step) + " is past the run's " + std::to_string(solver.total_steps()) +
           " steps");
  if (!is_time_of_step(state.time, solver, state.step))
    refuse("state.time " + std::to_string(state.time) + " is not the time of step " + std::to_string(state.step));
  for (const io::SeriesEntry& frame : checkpoint.series) {
    const int step = std::stoi(frame.file.substr(frame.file.find('_') + 1));  // "frame_%06d", checked when read
    const int every = scene.output.every;
    if (step > state.step || every <= 0 || step % every != 0 || !is_time_of_step(frame.time, solver, step))
      refuse("series entry " + frame.file + " is not a frame this run writes");
  }
}

}  // namespace

std::optional<Checkpoint> matching_checkpoint(const std::string& path, const Scene& scene, const Checkpoint& run) {
  if (!fs::exists(path)) return std::nullopt;
  Checkpoint checkpoint = read_checkpoint(path);
  if (checkpoint.mesh_fingerprint != run.mesh_fingerprint)
    throw InputError("checkpoint " + path + " was written for another mesh than " + scene.mesh +
                     " (remove it, or give another output.directory, to start afresh)");
  if (checkpoint.scene_fingerprint != run.scene_fingerprint)
    throw InputError("checkpoint " + path + " was written for another version of " + scene.path +
                     " (materials, constraints, loads, solver, adaptivity or output.every/track differ; remove it, "
                     "or give another output.directory, to start afresh)");
  check_against_run(checkpoint, path, scene);
  return checkpoint;
}

void check_checkpoint_state(const Checkpoint& checkpoint, const std::string& path, std::size_t dofs) {
  if (checkpoint.state.displacement.size() != dofs || checkpoint.state.velocity.size() != dofs)
    throw InputError("checkpoint " + path + ": its state does not fit the model's " + std::to_string(dofs) + " dofs");
}

}  // namespace tensormass::detail
