// Symplectic Euler (central differences with velocities at half steps) on
// the lumped mass: v += dt M^-1 (f - g(u) - alpha M v); u += dt v.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "solvers/integration_support.hpp"
#include "solvers/integrator_kinds.hpp"

namespace tensormass {

double estimate_stable_time_step(const Model& model, const Assembler& assembler, int iterations) {
  const int n = model.free_dof_count();
  const auto& free = model.free_dofs();
  std::vector<double> zero(model.dof_count(), 0.0), g(model.dof_count());
  SparseMatrix K = assembler.pattern();
  assembler.assemble(zero, g, &K);
  std::vector<double> inverse_sqrt_mass(n), x(n), y(n), w(n);
  for (int i = 0; i < n; ++i) inverse_sqrt_mass[i] = 1.0 / std::sqrt(model.lumped_mass()[free[i]]);
  // A fixed, non-special start vector (deterministic).
  for (int i = 0; i < n; ++i) x[i] = 1.0 + 0.5 * std::sin(1.0 + 12.9898 * i);
  double lambda = 0.0;
  for (int it = 0; it < iterations; ++it) {
    const double length = norm(x);
    for (double& value : x) value /= length;
    for (int i = 0; i < n; ++i) w[i] = inverse_sqrt_mass[i] * x[i];
    assembler.tangent_product(K, w, y);
    for (int i = 0; i < n; ++i) y[i] *= inverse_sqrt_mass[i];
    lambda = dot(x, y);
    x.swap(y);
  }
  return lambda > 0.0 ? 2.0 / std::sqrt(lambda) : INFINITY;
}

ExplicitIntegrator::ExplicitIntegrator(Integration& run) : Integrator(run) {
  run.statistics.stable_dt = estimate_stable_time_step(run.model, run.assembler);
  const double dt = run.settings.dt;
  if (dt > run.statistics.stable_dt) {
    std::ostringstream text;
    text << "dt = " << dt << " s exceeds the estimated stable time step " << run.statistics.stable_dt
         << " s: the explicit solve will likely blow up";
    run.statistics.warnings.push_back(text.str());
    std::fprintf(stderr, "tensormass: warning: %s\n", text.str().c_str());  // now, not after a long run
  }
}

void ExplicitIntegrator::step(State& state, const StepObserver& observer) {
  Integration& run = run_;
  const Model& model = run.model;
  const SolverSettings& settings = run.settings;
  const double dt = settings.dt, alpha = settings.damping_mass;
  const int dofs = model.dof_count();
  const auto& free = model.free_dofs();
  const auto& mass = model.lumped_mass();
  state.displacement.resize(dofs, 0.0);
  state.velocity.resize(dofs, 0.0);
  g_.resize(dofs);
  const int s = state.step + 1;
  const auto start = std::chrono::steady_clock::now();
  const double t = state.time, t1 = t + dt;
  auto& u = state.displacement;
  auto& v = state.velocity;
  detail::assemble(run, u, g_, nullptr);
  // One pass over the free dofs (the step's vector work is a visible share
  // of a folded Hooke step): external force at t, velocity, position.
  const double factor = model.load_factor(t);
  const auto& gravity = model.gravity_load();
  const auto& surface = model.surface_load();
  bool finite = true;
  for (int d : free) {
    v[d] += dt * ((factor * (gravity[d] + surface[d]) - g_[d]) / mass[d] - alpha * v[d]);
    u[d] += dt * v[d];
    finite = finite && std::isfinite(u[d]);
  }
  // Constrained dofs follow their prescribed path.
  for (const PrescribedDof& p : model.prescribed()) {
    const double next = model.prescribed_value(p, t1);
    v[p.dof] = (next - u[p.dof]) / dt;
    u[p.dof] = next;
  }
  if (!finite)
    detail::require_finite(u, "the displacement in step " + std::to_string(s) + " (t = " + std::to_string(t1) + " s)");
  state.time = t1;
  state.step = s;
  run.statistics.newton_per_step.push_back(0);
  run.statistics.step_ms.push_back(1e3 * detail::seconds_since(start));
  if (observer) observer(state);
}

void ExplicitIntegrator::finish(const State& state) {
  detail::require_no_inversion(run_.model, state.displacement, "at the end of the explicit run");
}

void solve_explicit(Integration& run, State& state, const StepObserver& observer) {
  ExplicitIntegrator integrator(run);
  integrator.run(state, observer);
}

}  // namespace tensormass
