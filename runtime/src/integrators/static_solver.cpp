// Static equilibrium g(u) = lambda f by Newton's method with load steps
// (halved where their start inverts a cell), a backtracking line search,
// and shifted tangents where K is not positive definite.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <sstream>

#include "integrators/integration_support.hpp"
#include "integrators/integrator_kinds.hpp"

namespace tensormass {

std::vector<double> external_force(const Model& model, double factor) {
  std::vector<double> f(model.dof_count());
  for (int dof = 0; dof < model.dof_count(); ++dof)
    f[dof] = factor * (model.gravity_load()[dof] + model.surface_load()[dof]);
  return f;
}

namespace {

/// r = g - f restricted to the free dofs.
void free_residual(const Model& model, const std::vector<double>& g, const std::vector<double>& f,
                   std::vector<double>& r) {
  const auto& free = model.free_dofs();
  for (std::size_t i = 0; i < free.size(); ++i) r[i] = g[free[i]] - f[free[i]];
}

std::string format_number(double x) {
  std::ostringstream text;
  text.precision(3);
  text << x;
  return text.str();
}

/// Potential energy W(u) - f.u of the static problem (W as assembled: blends, folded cells).
double potential(Integration& run, const detail::StateRows& rows, const std::vector<double>& u,
                 const std::vector<double>& f) {
  detail::PhaseTimer timer(run.statistics.assembly_seconds);
  return run.assembler.energy(u) - rows.dot_dofs(f, u);
}

/// The relative residual a Newton step's linear solve must reach (inexact
/// Newton): as loose as the relative nonlinear residual, between the
/// linear tolerance and 0.01. The residual after the step is then about
/// as small as an exact solve's (quadratic convergence), and a CG-based
/// solve does far fewer iterations early in a load step. (A cap of 0.1
/// cost 75 instead of 61 Newton iterations on the 15k-tet cantilever of
/// bench runtime; 0.01 cost 63, with half the linear iterations.)
double forcing(double relative_residual, double linear_tolerance) {
  return std::clamp(relative_residual, linear_tolerance, 0.01);
}

/// The shifts tried in turn where the tangent K is not positive definite:
/// K + shift |diag(K)| is, for a large enough shift, and its step descends
/// the potential energy (a Levenberg-Marquardt step), as the line search
/// needs. Compressed cells under a non-linear law right after a law switch
/// or a refinement give such tangents (geometric stiffness under
/// compressive stress); near the equilibrium K is positive definite again
/// and full Newton steps resume.
constexpr std::array<double, 5> kTangentShifts = {1e-3, 1e-2, 1e-1, 1.0, 10.0};

/// Solves K step = rhs (rhs = -r on the free dofs; step: zeros in, the
/// step out) for a step that descends the potential (rhs . step > 0), K
/// shifted by kTangentShifts where the factorisation finds it not positive
/// definite or its step does not descend (LDL^T solves some indefinite K).
/// K's values are spent either way. Returns whether it was shifted; throws
/// when even the largest shift leaves K singular (a row without stiffness).
bool solve_newton_step(Integration& run, const detail::StateRows& rows, SparseMatrix& K, std::span<const double> rhs,
                       std::span<double> step, double tolerance) {
  const auto descends = [&](std::span<const double> candidate) { return rows.dot_free(rhs, candidate) > 0; };
  try {
    detail::linear_solve(run, K, rhs, step, tolerance);
    if (descends(step)) return false;
  } catch (const NotPositiveDefiniteError&) {
  }
  std::vector<double> diagonal(K.rows);
  for (int i = 0; i < K.rows; ++i) diagonal[i] = std::abs(K.values[K.diagonal[i]]);
  double applied = 0.0;
  for (std::size_t attempt = 0;; ++attempt) {
    const bool last = attempt + 1 == kTangentShifts.size();
    for (int i = 0; i < K.rows; ++i) K.values[K.diagonal[i]] += (kTangentShifts[attempt] - applied) * diagonal[i];
    applied = kTangentShifts[attempt];
    std::fill(step.begin(), step.end(), 0.0);
    try {
      detail::linear_solve(run, K, rhs, step, tolerance);
      if (last || descends(step)) return true;
    } catch (const NotPositiveDefiniteError&) {
      if (last) throw;
    }
  }
}

std::string non_finite_residual(const std::string& where) {
  return "the residual " + where + " is not finite (NaN or infinity)";
}

/// Thrown by newton() when its starting point's residual is not finite (a
/// cell the predictor inverted under a law that cannot invert).
class NonFiniteStart : public NumericalError {
 public:
  using NumericalError::NumericalError;
};

/// A load step's starting point on the free dofs: the extrapolation of
/// order `order` (2: quadratic from the last three load steps, 1: linear
/// from the last two, 0: the last converged state) of the states in
/// `state` (the last), `previous` and `before_previous`.
std::vector<double> predicted_start(const Model& model, const State& state, const std::vector<double>& previous,
                                    const std::vector<double>& before_previous, int order) {
  std::vector<double> u = state.displacement;
  if (order == 2)
    for (int d : model.free_dofs()) u[d] += 2 * state.displacement[d] - 3 * previous[d] + before_previous[d];
  else if (order == 1)
    for (int d : model.free_dofs()) u[d] += state.displacement[d] - previous[d];
  return u;
}

/// The largest relative residual taken for a round-off floor: an
/// ill-conditioned tangent (a nearly incompressible material, nu 0.49 on a
/// fine mesh) leaves the exact linear solve's residual near 1e-8, where the
/// iterations only move round-off about.
constexpr double kFloorLimit = 1e-6;

/// The warning, once per run, that a load step stopped at its round-off floor.
void warn_of_floor(Integration& run, const std::string& where, double relative) {
  const std::string text = "Newton stopped at the round-off floor ";
  for (const std::string& w : run.statistics.warnings)
    if (w.rfind(text, 0) == 0) return;
  run.statistics.warnings.push_back(text + where + " (relative residual " + format_number(relative) +
                                    " above the tolerance " + format_number(run.settings.tolerance) +
                                    " and no longer falling: an ill-conditioned tangent)");
}

/// Newton iterations at a fixed load; returns the iterations used.
/// A full step is taken when it lowers the residual; otherwise the step
/// length is halved until the potential energy satisfies Armijo's condition
/// (bending-dominated StVK often raises the residual on the way to the
/// solution while the energy falls). Stops at the tolerance, or when the
/// residual stalls below 1e-8 (the round-off floor of g - f), or, with a
/// warning, below kFloorLimit when two iterations have not halved it.
int newton(Integration& run, std::vector<double>& u, const std::vector<double>& f, const std::string& where) {
  const Model& model = run.model;
  const SolverSettings& settings = run.settings;
  const int n = model.free_dof_count();
  const auto& free = model.free_dofs();
  std::vector<double> g(model.dof_count()), trial_g(model.dof_count()), trial_u(model.dof_count());
  std::vector<double> r(n), trial_r(n), step(n, 0.0), f_free(n);
  // One tangent: once the step is solved for, K's values are spent, and the
  // line search assembles the trial point's tangent into it (the accepted
  // trial's is the next iteration's).
  SparseMatrix K = run.assembler.pattern();
  const detail::StateRows rows(run.assembler);
  for (int i = 0; i < n; ++i) f_free[i] = f[free[i]];
  detail::assemble(run, u, g, &K);
  free_residual(model, g, f, r);
  double residual = rows.norm_free(r);
  if (!std::isfinite(residual)) throw NonFiniteStart(non_finite_residual(where));
  // The force scale the residual is measured against: the loads, or the
  // internal forces (with the reactions at fixed and prescribed dofs) when
  // those are larger. Without the latter, a load step whose start is
  // already the solution (a linear law under prescribed displacements,
  // extrapolated from the last steps) would compare round-off with itself.
  const double reference = std::max({rows.norm_free(f_free), residual, rows.norm_dofs(g), 1e-300});
  const bool debug = std::getenv("TENSORMASS_DEBUG_NEWTON") != nullptr;
  int shifted_steps = 0;
  double previous = INFINITY;  // the residual before the last iteration
  for (int iteration = 1; iteration <= settings.max_iterations; ++iteration) {
    if (residual <= settings.tolerance * reference) return iteration - 1;
    std::vector<double> rhs(n);
    for (int i = 0; i < n; ++i) rhs[i] = -r[i];
    std::fill(step.begin(), step.end(), 0.0);
    const bool shifted =
        solve_newton_step(run, rows, K, rhs, step, forcing(residual / reference, settings.linear.tolerance));
    shifted_steps += shifted;
    rows.share_ghost_free(step);
    const double slope = rows.dot_free(r, step);  // dPhi/dalpha at alpha = 0, negative for a descent step
    double alpha = 1.0, trial_residual = 0.0, energy = NAN;
    for (int halving = 0;; ++halving) {
      trial_u = u;
      for (int i = 0; i < n; ++i) trial_u[free[i]] += alpha * step[i];
      detail::assemble(run, trial_u, trial_g, &K);
      free_residual(model, trial_g, f, trial_r);
      trial_residual = rows.norm_free(trial_r);
      if (!std::isfinite(trial_residual)) {
        if (halving == 8) throw NumericalError("Newton produced a NaN residual " + where);
      } else if (trial_residual <= residual || halving == 8 || !(slope < 0)) {
        break;
      } else {
        if (std::isnan(energy)) energy = potential(run, rows, u, f);
        if (potential(run, rows, trial_u, f) <= energy + 1e-4 * alpha * slope) break;
      }
      alpha *= 0.5;
    }
    if (alpha < 1.0) ++run.statistics.shortened_steps;
    if (debug)
      std::fprintf(stderr, "newton %d: residual %.3e, step %.3g%s\n", iteration, trial_residual / reference, alpha,
                   shifted ? " (shifted tangent)" : "");
    const double earlier = previous;
    previous = residual;
    u.swap(trial_u);
    g.swap(trial_g);
    r.swap(trial_r);
    residual = trial_residual;
    if (residual <= settings.tolerance * reference) return iteration;
    if (alpha == 1.0 && residual <= 1e-8 * reference && residual > 0.1 * previous) return iteration;
    if (residual <= kFloorLimit * reference && residual > 0.5 * earlier) {
      warn_of_floor(run, where, residual / reference);
      return iteration;
    }
  }
  throw NumericalError("Newton did not converge " + where + " in " + std::to_string(settings.max_iterations) +
                       " iterations (relative residual " + format_number(residual / reference) + ", tolerance " +
                       format_number(settings.tolerance) + ")" +
                       (shifted_steps > 0 ? "; the tangent was not positive definite on " +
                                                std::to_string(shifted_steps) + " of them: is the body constrained?"
                                          : ""));
}

/// Newton at load factor `to` from `u` with the constraints at `to`
/// (u: in, and the solution out); the iterations, or none where the start's
/// residual is not finite (u unchanged then).
std::optional<int> newton_unless_non_finite(Integration& run, std::vector<double>& u, double to,
                                            const std::string& where) {
  std::vector<double> start = u;
  run.model.apply_constraints(to, start, true);
  try {
    const int iterations = newton(run, start, external_force(run.model, to), where);
    u.swap(start);
    return iterations;
  } catch (const NonFiniteStart&) {
    return std::nullopt;
  }
}

/// At most this many halvings of a load step's increment (1/16 of it).
constexpr int kMaxLoadCuts = 4;

/// Solves for equilibrium at load factor `to` from `u`, in equilibrium at
/// `from` (u: in, and the solution out). Where even that start leaves a
/// non-finite residual (the prescribed displacements' increment inverts a
/// cell next to them), the increment is halved, at most `cuts` times, and
/// the equilibria at the intermediate factors lead there. Returns the
/// Newton iterations of every solve.
int solve_with_cuts(Integration& run, std::vector<double>& u, double from, double to, const std::string& where,
                    int cuts) {
  if (const std::optional<int> iterations = newton_unless_non_finite(run, u, to, where)) return *iterations;
  if (cuts == 0 && from == to) throw NumericalError(non_finite_residual(where));
  if (cuts == 0)
    throw NumericalError(non_finite_residual(where) + " (the load increment halved " + std::to_string(kMaxLoadCuts) +
                         " times)");
  const double middle = 0.5 * (from + to);
  const int iterations = solve_with_cuts(run, u, from, middle, where, cuts - 1);
  return iterations + solve_with_cuts(run, u, middle, to, where, cuts - 1);
}

}  // namespace

void StaticIntegrator::step(State& state, const StepObserver& observer) {
  Integration& run = run_;
  const Model& model = run.model;
  const int steps = run.settings.load_steps;
  state.displacement.resize(model.dof_count(), 0.0);  // from rest, or from a restored load step
  state.velocity.resize(model.dof_count(), 0.0);
  // A load step solved again (the observer switched laws) counts once, with
  // the time and iterations of all its solves.
  double carried_ms = 0;
  int carried_iterations = 0;
  const int step = state.step + 1;
  // A static equilibrium is the long-term one: viscous stresses fully relaxed.
  run.assembler.begin_viscous_step({}, std::numeric_limits<double>::infinity());
  for (bool repeating = false;; repeating = true) {
    const auto start = std::chrono::steady_clock::now();
    const double factor = static_cast<double>(step) / steps;
    const std::string where = "in load step " + std::to_string(step) + "/" + std::to_string(steps);
    // Start from the quadratic extrapolation of the last three load steps
    // (linear with two): 2.55 Newton iterations per load step on the 15k-tet
    // cantilever of bench runtime, against 3.15 with the linear one. A
    // repeated step starts where it ended. A start whose residual is not
    // finite (the extrapolation inverted a cell: a probe's corner, a refined
    // mesh's small cells) falls back to the next lower order, and the last
    // converged state to halved load increments (solve_with_cuts).
    const std::vector<double> previous = state.previous_displacement;
    const std::vector<double> before_previous = state.earlier_displacement;
    const std::size_t dofs = state.displacement.size();
    const bool extrapolate = !repeating && previous.size() == dofs;
    const int highest = !extrapolate ? 0 : before_previous.size() == dofs ? 2 : 1;
    std::vector<double> u;
    std::optional<int> solved;
    for (int order = highest; order > 0 && !solved; --order) {
      u = predicted_start(model, state, previous, before_previous, order);
      solved = newton_unless_non_finite(run, u, factor, where);
    }
    if (!solved) {
      u = state.displacement;
      solved = solve_with_cuts(run, u, state.time, factor, where, repeating ? 0 : kMaxLoadCuts);
    }
    const int iterations = *solved;
    detail::require_no_inversion(run.assembler, u, where);
    run.statistics.newton_iterations += iterations;
    run.statistics.newton_per_step.push_back(carried_iterations + iterations);
    run.statistics.step_ms.push_back(carried_ms + 1e3 * detail::seconds_since(start));
    // The history the next load step extrapolates from travels with the
    // state the observer sees (a checkpoint of it resumes bit for bit).
    State next{u, state.velocity, factor, step, {}, state.displacement, previous, state.viscous_history};
    const bool repeat = observer && observer(next);
    if (repeat) next.previous_displacement = previous, next.earlier_displacement = before_previous;
    state = std::move(next);
    if (!repeat) return;
    carried_ms = run.statistics.step_ms.back();
    carried_iterations = run.statistics.newton_per_step.back();
    run.statistics.step_ms.pop_back();
    run.statistics.newton_per_step.pop_back();
    // and solve this load step again, from here, with the new laws
  }
}

void solve_static(Integration& run, State& state, const StepObserver& observer) {
  StaticIntegrator integrator(run);
  integrator.run(state, observer);
}

}  // namespace tensormass
