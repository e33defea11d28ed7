/// \file solver_settings.hpp
/// How a model is integrated, as plain data: the integrator, its steps and
/// tolerances, damping, the linear solver's settings and the thread count.
/// Filled and validated by the scene reader (scene/) or by another front end.
#ifndef TENSORMASS_INTEGRATORS_SOLVER_SETTINGS_HPP
#define TENSORMASS_INTEGRATORS_SOLVER_SETTINGS_HPP

#include <string_view>

#include "tensormass/linear_solvers/linear_solver_settings.hpp"

namespace tensormass {

/// Static Newton with load steps, implicit (backward) Euler, explicit symplectic Euler.
enum class SolverType { static_newton, implicit_euler, explicit_euler };
/// Where an implicit step's Newton iterations start for the free dofs:
/// u0 + dt v0 (the motion continued), or u0 (only the prescribed dofs moved).
enum class StepPredictor { velocity, none };

/// The scene's names: "static", "implicit", "explicit".
std::string_view solver_type_name(SolverType type);
/// The scene's names: "velocity", "none".
std::string_view step_predictor_name(StepPredictor predictor);

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
