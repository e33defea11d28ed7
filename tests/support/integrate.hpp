// Helpers of the solver tests: one integrator run on a mesh, and the mean
// vertical displacement of a beam's tip.
#ifndef TENSORMASS_TESTS_SOLVERS_INTEGRATE_HPP
#define TENSORMASS_TESTS_SOLVERS_INTEGRATE_HPP

#include <memory>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/integrators/integrators.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass::test {

/// Runs one integrator on `mesh` and returns the final state.
inline State integrate(const Mesh& mesh, const Scene& scene, SolveStatistics& statistics,
                       const StepObserver& observer = {}) {
  const Model model(mesh, scene.model);
  Assembler assembler(model);
  assembler.set_hessian_projection(scene.solver.project_hessian);
  auto linear = make_linear_solver(scene.solver.linear);
  Integration run{model, assembler, *linear, scene.solver, statistics};
  State state;
  if (scene.solver.type == SolverType::static_newton) solve_static(run, state, observer);
  else if (scene.solver.type == SolverType::implicit_euler) solve_implicit(run, state, observer);
  else solve_explicit(run, state, observer);
  return state;
}

inline double tip_deflection(const Mesh& mesh, const State& state) {
  double sum = 0;
  const Group& tip = *mesh.group("tip");
  for (int node : tip.nodes) sum += state.displacement[node * mesh.dim + 1];
  return sum / tip.nodes.size();
}

}  // namespace tensormass::test

#endif
