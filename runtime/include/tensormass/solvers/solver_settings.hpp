/// \file solver_settings.hpp
/// How a model is integrated, as plain data: the integrator, its steps and
/// tolerances, damping, the linear solver and the thread count. Filled and
/// validated by the scene reader (scene/) or by another front end.
#ifndef TENSORMASS_SOLVERS_SOLVER_SETTINGS_HPP
#define TENSORMASS_SOLVERS_SOLVER_SETTINGS_HPP

#include <string>
#include <string_view>

namespace tensormass {

/// Static Newton with load steps, implicit (backward) Euler, explicit symplectic Euler.
enum class SolverType { static_newton, implicit_euler, explicit_euler };
enum class LinearSolverType { cholmod, cg, petsc };
/// Where an implicit step's Newton iterations start for the free dofs:
/// u0 + dt v0 (the motion continued), or u0 (only the prescribed dofs moved).
enum class StepPredictor { velocity, none };

/// The scene's names: "static", "implicit", "explicit"; "cholmod", "cg", "petsc".
std::string_view solver_type_name(SolverType type);
std::string_view linear_solver_type_name(LinearSolverType type);
/// The scene's names: "velocity", "none".
std::string_view step_predictor_name(StepPredictor predictor);

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

struct SolverSettings {
  SolverType type = SolverType::static_newton;
  // static
  int load_steps = 1;
  double tolerance = 1e-10;  ///< Newton: relative residual
  int max_iterations = 50;   ///< Newton iterations per load step
  // dynamic
  double dt = 0;                 ///< > 0 for implicit and explicit
  int steps = 0;                 ///< > 0 for implicit and explicit
  int newton_iterations = 1;     ///< implicit: Newton iterations per step (1 = linearised step)
  double damping_mass = 0;       ///< Rayleigh alpha (1/s)
  double damping_stiffness = 0;  ///< Rayleigh beta (s); not with the explicit solver
  /// implicit: the start of each step's Newton iterations. Starting from u0
  /// with only the prescribed dofs moved squashes the cells next to them
  /// before the first tangent (thin cells on a moving boundary invert).
  StepPredictor predictor = StepPredictor::velocity;
  /// static and implicit: project each kernel cell's Hessian to positive
  /// semi-definite (Assembler::set_hessian_projection)
  bool project_hessian = false;
  LinearSolverSettings linear;
  int threads = 0;  ///< 0 = OpenMP default

  bool is_static() const { return type == SolverType::static_newton; }
  bool is_dynamic() const { return !is_static(); }
  /// Load steps (static) or time steps (dynamic).
  int total_steps() const { return is_static() ? load_steps : steps; }
};

}  // namespace tensormass

#endif
