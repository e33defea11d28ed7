// Backward Euler: M (v1 - v0) / dt = f(t1) - g(u1) - C v1, u1 = u0 + dt v1,
// with Rayleigh damping C = alpha M + beta K(u). Newton on u1 starting at
// u0, so one iteration is the classic linearised step (Baraff-Witkin).
#include <algorithm>
#include <chrono>
#include <cmath>

#include "solvers/integration_support.hpp"

namespace tensormass {

void solve_implicit(Integration& run, State& state, const StepObserver& observer) {
  const Model& model = run.model;
  const SolverSettings& settings = run.settings;
  const double dt = settings.dt, alpha = settings.damping_mass, beta = settings.damping_stiffness;
  const int n = model.free_dof_count(), dofs = model.dof_count();
  const auto& free = model.free_dofs();
  const auto& mass = model.lumped_mass();
  state.displacement.resize(dofs, 0.0);
  state.velocity.resize(dofs, 0.0);
  std::vector<double> g(dofs), v(dofs), r(n), step(n, 0.0), damping(n), kv(n), v_free(n);
  SparseMatrix K = run.assembler.pattern(), J = run.assembler.pattern();
  const double mass_factor = 1.0 / (dt * dt) + alpha / dt, stiffness_factor = 1.0 + beta / dt;
  for (int s = 1; s <= settings.steps; ++s) {
    const auto start = std::chrono::steady_clock::now();
    const double t1 = state.time + dt;
    const std::string where = "in step " + std::to_string(s) + " (t = " + std::to_string(t1) + " s)";
    const std::vector<double> u0 = state.displacement, v0 = state.velocity;
    std::vector<double> u = u0;
    model.apply_constraints(t1, u);
    const std::vector<double> f = external_force(model, model.load_factor(t1));
    double reference = 0.0;
    int iterations = 0;
    for (int iteration = 1; iteration <= settings.newton_iterations; ++iteration) {
      detail::assemble(run, u, g, &K);
      for (int d = 0; d < dofs; ++d) v[d] = (u[d] - u0[d]) / dt;
      for (int i = 0; i < n; ++i) v_free[i] = v[free[i]];
      if (beta != 0.0) K.multiply(v_free, kv);
      for (int i = 0; i < n; ++i) {
        const int d = free[i];
        r[i] = mass[d] * ((v[d] - v0[d]) / dt + alpha * v[d]) + (beta != 0.0 ? beta * kv[i] : 0.0) + g[d] - f[d];
      }
      detail::require_finite(r, "the residual " + where);
      const double residual = norm(r);
      if (iteration == 1) reference = std::max(residual, 1e-300);
      else if (residual <= settings.tolerance * reference) break;
      // J = (1/dt^2 + alpha/dt) M + (1 + beta/dt) K
      for (int k = 0; k < K.nonzeros(); ++k) J.values[k] = stiffness_factor * K.values[k];
      for (int i = 0; i < n; ++i) J.values[J.diagonal[i]] += mass_factor * mass[free[i]];
      for (double& x : r) x = -x;
      detail::linear_solve(run, J, r, step);  // warm start: the previous correction
      for (int i = 0; i < n; ++i) u[free[i]] += step[i];
      iterations = iteration;
    }
    detail::require_finite(u, "the displacement " + where);
    detail::require_no_inversion(model, u, where);
    for (int d = 0; d < dofs; ++d) v[d] = (u[d] - u0[d]) / dt;
    state.displacement = std::move(u);
    state.velocity = v;
    state.time = t1;
    state.step = s;
    run.statistics.newton_iterations += iterations;
    run.statistics.newton_per_step.push_back(iterations);
    run.statistics.step_ms.push_back(1e3 * detail::seconds_since(start));
    if (observer) observer(state);
  }
}

}  // namespace tensormass
