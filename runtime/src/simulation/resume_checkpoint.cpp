#include "simulation/resume_checkpoint.hpp"

#include <filesystem>

#include "tensormass/common/errors.hpp"

namespace tensormass::detail {

namespace fs = std::filesystem;

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
  return checkpoint;
}

void check_checkpoint_state(const Checkpoint& checkpoint, const std::string& path, std::size_t dofs) {
  if (checkpoint.state.displacement.size() != dofs || checkpoint.state.velocity.size() != dofs)
    throw InputError("checkpoint " + path + ": its state does not fit the model's " + std::to_string(dofs) + " dofs");
}

}  // namespace tensormass::detail
