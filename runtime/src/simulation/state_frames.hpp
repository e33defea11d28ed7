// A state written as a VTU frame: displacement and velocity as point data,
// law, element type, material, level and the adaptive model's fields as
// cell data. Internal header.
#ifndef TENSORMASS_SIMULATION_STATE_FRAMES_HPP
#define TENSORMASS_SIMULATION_STATE_FRAMES_HPP

#include <span>
#include <string>

#include "tensormass/adaptivity/adaptivity.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/parallel/distribution.hpp"

namespace tensormass::detail {

/// `name`.vtu in `directory` on one process; over MPI ranks, each rank's
/// piece `name`_p<rank>.vtu (its cells) and, from rank 0, `name`.pvtu.
/// `levels`: per cell, its refinement level (empty without refinement).
/// Returns the file to name in a series.
std::string write_state(const std::string& directory, const std::string& name, const Model& model, const State& state,
                        std::span<const int> levels, const Adaptivity* adaptivity, const Distribution* distribution);

}  // namespace tensormass::detail

#endif
