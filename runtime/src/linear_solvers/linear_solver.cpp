// The parts of the LinearSolver interface every solver shares, and the
// factory that picks one from the settings.
#include "tensormass/linear_solvers/linear_solver.hpp"

#include "tensormass/common/errors.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {

std::unique_ptr<LinearSolver> make_cholmod_solver(const LinearSolverSettings& settings);
std::unique_ptr<LinearSolver> make_cg_solver(const LinearSolverSettings& settings);
std::unique_ptr<LinearSolver> make_petsc_solver(const LinearSolverSettings& settings);

void LinearSolver::distribute(const Distribution&) {
  throw InputError("the " + name() +
                   " linear solver runs on one process; on several MPI ranks use solver.backend: petsc");
}

void LinearSolver::restore_state(std::span<const double> saved, const SparseMatrix&) {
  if (!saved.empty())
    throw InputError("the checkpoint holds a direct solver's factor; this run's linear solver (" + name() +
                     ") keeps none");
}

void describe_free_nodes(LinearSolver& solver, const Model& model) {
  const int d = model.dim();
  const auto& free = model.free_dofs();
  if (free.size() % d != 0) return;
  std::vector<double> coordinates;
  coordinates.reserve(free.size());
  for (std::size_t block = 0; block < free.size(); block += d) {
    const int node = free[block] / d;
    for (int a = 0; a < d; ++a)
      if (free[block + a] != node * d + a) return;  // a node with only some components free
    for (int a = 0; a < d; ++a)
      coordinates.push_back(model.mesh().rest_positions[3 * static_cast<std::size_t>(node) + a]);
  }
  solver.set_node_blocks(d, coordinates);
}

std::unique_ptr<LinearSolver> make_linear_solver(const LinearSolverSettings& settings) {
  if (settings.type == LinearSolverType::cg) return make_cg_solver(settings);
  if (settings.type == LinearSolverType::petsc) return make_petsc_solver(settings);
  return make_cholmod_solver(settings);
}

}  // namespace tensormass
