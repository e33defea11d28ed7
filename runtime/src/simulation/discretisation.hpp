// What a run computes on: the mesh and everything built on it (model,
// distribution among MPI ranks, assembler, solvers), and the mesh a rank
// starts from (the whole mesh, or its part of it). Internal header.
#ifndef TENSORMASS_SIMULATION_DISCRETISATION_HPP
#define TENSORMASS_SIMULATION_DISCRETISATION_HPP

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tensormass/assembly/assembler.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/mesh/mesh.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/parallel/distribution.hpp"
#include "tensormass/parallel/mesh_broadcast.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/simulation.hpp"
#include "tensormass/simulation/track.hpp"

namespace tensormass::detail {

/// The mesh and everything built on it: replaced as a whole when
/// refinement changes the mesh. `cut`: set when the mesh is this rank's part.
struct Discretisation {
  Discretisation(Mesh mesh_in, const Scene& scene, SolveStatistics& statistics,
                 std::optional<CellCut> cut = std::nullopt);
  /// What the solvers need before the first step (after any distribution).
  void prepare(const Scene& scene);
  /// Cells, nodes and free dofs of the whole mesh.
  int whole_cell_count() const {
    return distribution && distribution->holds_part() ? distribution->whole_cell_count() : mesh.cell_count();
  }
  int whole_node_count() const { return distribution ? distribution->whole_node_count() : mesh.node_count(); }
  int whole_free_dof_count() const {
    return distribution && distribution->holds_part() ? distribution->global_row_count() : model.free_dof_count();
  }

  Mesh mesh;
  Model model;
  std::unique_ptr<Distribution> distribution;  // null on one process; before the assembler, which uses it
  Assembler assembler;
  std::unique_ptr<LinearSolver> linear;
  Integration integration;
  /// The integrator, made at its first use: the explicit one estimates dt
  /// from the laws then, and a refined mesh gets its own.
  Integrator& stepper() {
    if (!integrator) integrator = make_integrator(integration);
    return *integrator;
  }
  std::unique_ptr<Integrator> integrator;
};

/// What this rank starts from: the whole mesh, or over several MPI ranks
/// its part of it, with what only the whole mesh tells.
struct StartMesh {
  Mesh mesh;
  std::optional<CellCut> cut;      ///< set when `mesh` is this rank's part, checked against the scene on rank 0
  std::uint64_t fingerprint = 0;   ///< with cut: the whole mesh's
  std::vector<GroupTrack> tracks;  ///< with cut: rank 0's, made on the whole mesh (the others record none)
};

/// A whole mesh held by this process, uncut.
StartMesh whole_start_mesh(Mesh mesh);

/// The scene's mesh checked against the scene (a part was checked whole, on rank 0).
Mesh checked_mesh(const Scene& scene, StartMesh& start);

/// The scene's mesh as this rank holds it: rank 0 reads the file, checks it
/// against the scene and cuts it (when each rank holds only its part: runs
/// that refine, that save or restore every cell's adaptive state, or whose
/// caller asks for it keep the whole mesh on every rank), then sends each
/// rank its part; the reader's and the whole mesh's memory stay on rank 0,
/// for a while.
StartMesh read_start_mesh(const Scene& scene, const RunOptions& options);

/// One track per `output.track` group (the groups were checked before).
std::vector<GroupTrack> make_tracks(const Scene& scene, const Mesh& mesh);

}  // namespace tensormass::detail

#endif
