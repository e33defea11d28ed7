/// \file linear_solver_settings.hpp
/// Which linear solver an integrator's systems go to, and its tolerances,
/// as plain data (SolverSettings::linear).
#ifndef TENSORMASS_LINEAR_SOLVERS_LINEAR_SOLVER_SETTINGS_HPP
#define TENSORMASS_LINEAR_SOLVERS_LINEAR_SOLVER_SETTINGS_HPP

#include <string>
#include <string_view>

namespace tensormass {

enum class LinearSolverType { cholmod, cg, petsc };

/// The scene's names: "cholmod", "cg", "petsc".
std::string_view linear_solver_type_name(LinearSolverType type);

struct LinearSolverSettings {
  LinearSolverType type = LinearSolverType::cholmod;
  /// cg, petsc, and cholmod's CG with an old factor: relative residual.
  /// 1e-6, not 1e-10: a linearised implicit step (one Newton iteration) has
  /// no use for more digits (docs/results/adaptive.md); static
  /// Newton solves ask for less while their residual is large.
  double tolerance = 1e-6;
  int max_iterations = 10000;  ///< cg
  /// cholmod: when the matrix changed, first try at most this many CG
  /// iterations preconditioned by the previous factor (0 = always refactorise)
  int reuse_iterations = 12;
  /// petsc: PETSc options for its Krylov solver and preconditioner (the
  /// `-ksp_*` and `-pc_*` of PETSc's manual), read after these defaults;
  /// `tolerance` and `max_iterations` set -ksp_rtol and -ksp_max_it.
  std::string petsc_options = "-ksp_type cg -pc_type gamg";
};

}  // namespace tensormass

#endif
