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
#include <memory>
#include <string>
#include <vector>

#include "tensormass/assembly/assembler.hpp"
#include "tensormass/integrators/solver_settings.hpp"
#include "tensormass/integrators/step_series.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/model/model.hpp"

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
  /// The viscous history at `time` (Assembler::viscous_part(): its
  /// history_size() doubles); empty for an elastic model or before the first step.
  std::vector<double> viscous_history;
};

/// Wall-clock seconds per phase and iteration counts, accumulated.
struct SolveStatistics {
  double assembly_seconds = 0;
  double solve_seconds = 0;  ///< factorisation and linear solves
  int newton_iterations = 0;
  int shortened_steps = 0;  ///< Newton steps the line search cut below full length
  long linear_iterations = 0;
  int factorizations = 0;           ///< numeric factorisations of a direct solver
  StepSeries<int> newton_per_step;  ///< per step (load step)
  StepSeries<double> step_ms;       ///< wall time of each step
  double stable_dt = 0;             ///< explicit: the estimated stable time step
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

/// Steps a run one step (static: one load step) at a time and keeps its
/// workspace between steps; everything carried from step to step is in
/// State, so stepping one call at a time gives the whole run bit for bit.
class Integrator {
 public:
  explicit Integrator(Integration& run) : run_(run) {}
  virtual ~Integrator() = default;
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  /// True once `state` holds the settings' last step (load step).
  bool finished(const State& state) const { return state.step >= run_.settings.total_steps(); }
  /// Advances `state` by one step and reports it to `observer` (a static
  /// load step is solved again while the observer asks). Requires !finished(state).
  virtual void step(State& state, const StepObserver& observer) = 0;
  /// The checks at the end of a run (explicit: no inverted cell).
  virtual void finish(const State&) {}
  /// Steps until finished, then finish().
  void run(State& state, const StepObserver& observer);

 protected:
  Integration& run_;
};

/// The integrator of run.settings.type. The explicit one estimates the
/// stable time step here (with the model's laws as they are now).
std::unique_ptr<Integrator> make_integrator(Integration& run);

/// Whole runs from `state` (state.step steps done), by the integrators above.
void solve_static(Integration& run, State& state, const StepObserver& observer);
void solve_implicit(Integration& run, State& state, const StepObserver& observer);
void solve_explicit(Integration& run, State& state, const StepObserver& observer);

/// The largest stable explicit time step 2 / omega_max, omega_max^2 the
/// largest eigenvalue of M^-1/2 K M^-1/2 at rest over the free dofs, from at
/// most `iterations` Lanczos steps (it stops once the estimate settles to
/// 1e-8). Matrix-free: each product is a central difference of two force
/// assemblies, so no tangent is held.
double estimate_stable_time_step(const Model& model, const Assembler& assembler, int iterations = 100);

/// External force (dof_count) at load factor `factor`: gravity + surface loads.
std::vector<double> external_force(const Model& model, double factor);

}  // namespace tensormass

#endif
