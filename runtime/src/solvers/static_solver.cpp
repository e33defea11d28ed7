// Static equilibrium g(u) = lambda f by Newton's method with load steps and
// a backtracking line search on the residual norm.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "integration_support.hpp"

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

/// Newton iterations at a fixed load; returns the iterations used.
int newton(Integration& run, std::vector<double>& u, const std::vector<double>& f, const std::string& where) {
  const Model& model = run.model;
  const SolverSpec& spec = run.scene.solver;
  const int n = model.free_dof_count();
  std::vector<double> g(model.dof_count()), trial_g(model.dof_count()), trial_u(model.dof_count());
  std::vector<double> r(n), trial_r(n), step(n, 0.0), f_free(n);
  SparseMatrix K = run.assembler.pattern(), trial_K = run.assembler.pattern();
  for (int i = 0; i < n; ++i) f_free[i] = f[model.free_dofs()[i]];
  detail::assemble(run, u, g, &K);
  free_residual(model, g, f, r);
  detail::require_finite(r, "the residual " + where);
  const double reference = std::max({norm(f_free), norm(r), 1e-300});
  double residual = norm(r);
  for (int iteration = 1; iteration <= spec.max_iterations; ++iteration) {
    if (residual <= spec.tolerance * reference) return iteration - 1;
    for (double& x : r) x = -x;
    std::fill(step.begin(), step.end(), 0.0);
    detail::linear_solve(run, K, r, step);
    // Backtracking: halve the step until the residual decreases (at most 8 times).
    double alpha = 1.0, trial_residual = 0.0;
    for (int halving = 0;; ++halving) {
      trial_u = u;
      for (int i = 0; i < n; ++i) trial_u[model.free_dofs()[i]] += alpha * step[i];
      detail::assemble(run, trial_u, trial_g, &trial_K);
      free_residual(model, trial_g, f, trial_r);
      trial_residual = norm(trial_r);
      if ((std::isfinite(trial_residual) && trial_residual <= (1.0 - 1e-4 * alpha) * residual) || halving == 8) break;
      alpha *= 0.5;
    }
    if (!std::isfinite(trial_residual)) throw NumericalError("Newton produced a NaN residual " + where);
    u.swap(trial_u);
    g.swap(trial_g);
    r.swap(trial_r);
    std::swap(K, trial_K);
    residual = trial_residual;
    // A step at round-off level cannot improve u any further.
    const double step_size = alpha * detail::max_abs(step);
    if (residual <= spec.tolerance * reference || step_size <= 1e-13 * std::max(detail::max_abs(u), 1e-300))
      return iteration;
  }
  throw NumericalError("Newton did not converge " + where + " in " + std::to_string(spec.max_iterations) +
                       " iterations (relative residual " + format_number(residual / reference) +
                       ", tolerance " + format_number(spec.tolerance) + ")");
}

}  // namespace

void solve_static(Integration& run, State& state, const StepObserver& observer) {
  const Model& model = run.model;
  const int steps = run.scene.solver.load_steps;
  state.displacement.assign(model.dof_count(), 0.0);
  state.velocity.assign(model.dof_count(), 0.0);
  for (int step = 1; step <= steps;) {
    const auto start = std::chrono::steady_clock::now();
    const double factor = static_cast<double>(step) / steps;
    const std::string where = "in load step " + std::to_string(step) + "/" + std::to_string(steps);
    std::vector<double> u = state.displacement;
    model.apply_constraints(factor, u, true);
    const int iterations = newton(run, u, external_force(model, factor), where);
    detail::require_no_inversion(model, u, where);
    run.statistics.newton_iterations += iterations;
    run.statistics.newton_per_step.push_back(iterations);
    run.statistics.step_ms.push_back(1e3 * detail::seconds_since(start));
    State next{u, state.velocity, factor, step};
    const bool repeat = observer && observer(next);
    state = std::move(next);
    // When the observer changed laws, this load step is solved again from
    // here, so the final state is in equilibrium for the final laws.
    if (!repeat) ++step;
  }
}

}  // namespace tensormass
