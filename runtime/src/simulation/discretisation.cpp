#include "simulation/discretisation.hpp"

#include <cstring>
#include <utility>

#include "tensormass/io/read_mesh.hpp"
#include "tensormass/parallel/cell_partition.hpp"
#include "tensormass/parallel/mpi_world.hpp"
#include "tensormass/parallel/rank_errors.hpp"
#include "tensormass/simulation/checkpoint.hpp"

namespace tensormass::detail {

namespace {

/// Over several MPI ranks, the cut of the model's cells among them (rank 0
/// partitions, every rank gets the same); nullptr on one process.
std::unique_ptr<Distribution> cut_among_ranks(const Model& model) {
  const int ranks = parallel::world_size(), rank = parallel::world_rank();
  if (ranks <= 1) return nullptr;
  std::vector<int> cell_owner =
      rank == 0 ? parallel::partition_cells(model.mesh(), ranks) : std::vector<int>(model.cell_count(), 0);
  parallel::broadcast_from_root(cell_owner);
  return std::make_unique<Distribution>(model, std::move(cell_owner), rank, ranks);
}

/// The distribution of a model: over a rank's part of the mesh (`cut`), or
/// of the whole mesh cut here (cut_among_ranks).
std::unique_ptr<Distribution> distribute(const Model& model, std::optional<CellCut> cut) {
  if (!cut) return cut_among_ranks(model);
  return std::make_unique<Distribution>(model, std::move(*cut), parallel::world_rank(), parallel::world_size());
}

/// A model of a rank's part of the mesh: its node sums and energy scale
/// completed from every rank's part.
void complete_model_sums(Model& model, const Distribution& distribution) {
  double energy_scale = 0.0;
  for (int cell = 0; cell < model.cell_count(); ++cell)
    if (distribution.owns_cell(cell)) energy_scale += model.cell_energy_scale(cell);
  model.complete_partial_sums([&](std::span<double> v) { distribution.complete_dofs(v); },
                              parallel::sum_over_ranks(energy_scale));
}

/// The model of `mesh`. Over ranks that each hold their part of a mesh
/// (`collective`), an error building one rank's (an element inverted at
/// rest) is thrown on every rank, so none waits for it in the next step.
Model build_model(const Mesh& mesh, const ModelSpec& spec, bool collective) {
  if (!collective) return Model(mesh, spec);
  std::optional<Model> model;
  parallel::on_every_rank([&] { model.emplace(mesh, spec); });
  return std::move(*model);
}

/// Whether each MPI rank holds only its part of the mesh. Runs that refine
/// the mesh (every rank refines the whole of it alike), that save or
/// restore every cell's adaptive state, or whose caller asks for it
/// (Python scripts) keep the whole mesh on every rank.
bool cuts_mesh(const Scene& scene, const RunOptions& options) {
  if (parallel::world_size() == 1 || scene.refinement.enabled || options.whole_mesh_on_every_rank) return false;
  return !(scene.adaptivity.enabled && (options.resume || scene.output.checkpoint_every > 0));
}

}  // namespace

Discretisation::Discretisation(Mesh mesh_in, const Scene& scene, SolveStatistics& statistics,
                               std::optional<CellCut> cut)
    : mesh(std::move(mesh_in)),
      model(build_model(mesh, scene.model, cut.has_value())),
      distribution(distribute(model, std::move(cut))),
      assembler(model, true, distribution.get()),
      linear(make_linear_solver(scene.solver.linear)),
      integration{model, assembler, *linear, scene.solver, statistics} {
  if (distribution && distribution->holds_part()) {
    complete_model_sums(model, *distribution);
    distribution->number_global_rows();
  }
}

void Discretisation::prepare(const Scene& scene) {
  assembler.set_hessian_projection(scene.solver.project_hessian);
  describe_free_nodes(*linear, model);
}

StartMesh whole_start_mesh(Mesh mesh) {
  StartMesh start;
  start.mesh = std::move(mesh);
  return start;
}

Mesh checked_mesh(const Scene& scene, StartMesh& start) {
  if (!start.cut) validate_against_mesh(scene, start.mesh);
  return std::move(start.mesh);
}

StartMesh read_start_mesh(const Scene& scene, const RunOptions& options) {
  if (!cuts_mesh(scene, options)) return whole_start_mesh(parallel::read_mesh_on_root(scene.mesh));
  StartMesh start;
  Mesh whole;
  std::vector<int> cell_owner;
  parallel::on_root([&] {
    whole = read_mesh(scene.mesh);
    validate_against_mesh(scene, whole);
    start.fingerprint = mesh_fingerprint(whole);
    start.tracks = make_tracks(scene, whole);
    cell_owner = parallel::partition_cells(whole, parallel::world_size());
  });
  MeshPart part =
      parallel::world_rank() == 0 ? parallel::send_mesh_parts(whole, cell_owner) : parallel::receive_mesh_part();
  std::vector<char> fingerprint(sizeof start.fingerprint);
  std::memcpy(fingerprint.data(), &start.fingerprint, sizeof start.fingerprint);
  parallel::broadcast_bytes_from_root(fingerprint);
  std::memcpy(&start.fingerprint, fingerprint.data(), sizeof start.fingerprint);
  start.mesh = std::move(part.mesh);
  start.cut = std::move(part.cut);
  return start;
}

std::vector<GroupTrack> make_tracks(const Scene& scene, const Mesh& mesh) {
  std::vector<GroupTrack> tracks;
  for (const std::string& name : scene.output.track) tracks.emplace_back(mesh, *mesh.group(name));
  return tracks;
}

}  // namespace tensormass::detail
