// The checkpoint a resumed run continues from: the output directory's, when
// it was written by this scene on this mesh. Internal header.
#ifndef TENSORMASS_SIMULATION_RESUME_CHECKPOINT_HPP
#define TENSORMASS_SIMULATION_RESUME_CHECKPOINT_HPP

#include <cstddef>
#include <optional>
#include <string>

#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/checkpoint.hpp"

namespace tensormass::detail {

/// The checkpoint at `path` when there is one, checked against this run's
/// fingerprints (`run`); InputError when it belongs to another run.
std::optional<Checkpoint> matching_checkpoint(const std::string& path, const Scene& scene, const Checkpoint& run);

/// InputError unless the checkpoint's state fits the model's dofs.
/// `dofs`: the whole mesh's.
void check_checkpoint_state(const Checkpoint& checkpoint, const std::string& path, std::size_t dofs);

}  // namespace tensormass::detail

#endif
