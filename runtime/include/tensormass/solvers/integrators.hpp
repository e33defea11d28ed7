/// \file integrators.hpp
/// Time and load stepping on a Model: static Newton with load steps and a
/// backtracking line search, implicit (backward) Euler with Newton
/// iterations and Rayleigh damping, and explicit symplectic Euler with the
/// lumped mass. Every integrator reports each finished step to a
/// StepObserver and throws NumericalError (what failed, where) on
/// divergence, NaN or an inverted element.
#ifndef TENSORMASS_INTEGRATORS_HPP
#define TENSORMASS_INTEGRATORS_HPP

#include <functional>
#include <string>
#include <vector>

#include "tensormass/assembly/assembler.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/solvers/linear_solver.hpp"
#include "tensormass/solvers/solver_settings.hpp"

namespace tensormass {

/// The mechanical state, dof_count() each, and what an integrator carries
/// from one step to the next: an integrator continues from `step`, so a run
/// restored from a checkpoint goes on bit for bit.
struct State {
  std::vector<double> displacement;
  std::vector<double> velocity;
  double time = 0;  ///< seconds (dynamic) or load factor in [0, 1] (static)
  int step = 0;     ///< steps (load steps) completed
  /// implicit: the last Newton correction (free dofs), where the next linear solve starts
  std::vector<double> warm_start;
  /// static: the converged displacements of the two load steps before this
  /// one (the predictor's extrapolation); empty until there are any
  std::vector<double> previous_displacement, earlier_displacement;
};

/// Wall-clock seconds per phase and iteration counts, accumulated.
struct SolveStatistics {
  double assembly_seconds = 0;
  double solve_seconds = 0;  ///< factorisation and linear solves
  int newton_iterations = 0;
  int shortened_steps = 0;  ///< Newton steps the line search cut below full length
  long linear_iterations = 0;
  int factorizations = 0;            ///< numeric factorisations of a direct solver
  std::vector<int> newton_per_step;  ///< per step (load step)
  std::vector<double> step_ms;       ///< wall time of each step
  double stable_dt = 0;              ///< explicit: the estimated stable time step
  std::vector<std::string> warnings;
};

/// Called after each finished step with the new state; the driver writes
/// frames and progress here. It may also run the adaptive criteria: a
/// return value of true asks a static solve to repeat the load step.
using StepObserver = std::function<bool(const State&)>;

/// Everything an integrator works with.
struct Integration {
  const Model& model;
  const Assembler& assembler;
  LinearSolver& linear;
  const SolverSettings& settings;
  SolveStatistics& statistics;
};

void solve_static(Integration& run, State& state, const StepObserver& observer);
void solve_implicit(Integration& run, State& state, const StepObserver& observer);
void solve_explicit(Integration& run, State& state, const StepObserver& observer);

/// The largest stable explicit time step 2 / omega_max, omega_max^2 from
/// power iterations on M^-1/2 K M^-1/2 at rest over the free dofs.
double estimate_stable_time_step(const Model& model, const Assembler& assembler, int iterations = 100);

/// External force (dof_count) at load factor `factor`: gravity + surface loads.
std::vector<double> external_force(const Model& model, double factor);

}  // namespace tensormass

#endif
