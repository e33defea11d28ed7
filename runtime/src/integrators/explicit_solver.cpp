// Symplectic Euler (central differences with velocities at half steps) on
// the lumped mass: v += dt M^-1 (f - g(u) - alpha M v); u += dt v.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "integrators/integration_support.hpp"
#include "integrators/integrator_kinds.hpp"

namespace tensormass {

namespace {

/// The largest eigenvalue of the symmetric tridiagonal matrix with diagonal
/// `a` and off-diagonal `b` (a.size() - 1 entries), by bisection on Sturm
/// counts between Gershgorin's bounds.
double largest_tridiagonal_eigenvalue(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t m = a.size();
  double low = INFINITY, high = -INFINITY;
  for (std::size_t i = 0; i < m; ++i) {
    const double radius = (i > 0 ? std::abs(b[i - 1]) : 0.0) + (i + 1 < m ? std::abs(b[i]) : 0.0);
    low = std::min(low, a[i] - radius);
    high = std::max(high, a[i] + radius);
  }
  // The number of eigenvalues below x: the negative pivots of T - x I.
  const auto below = [&](double x) {
    std::size_t count = 0;
    double pivot = 1.0;
    for (std::size_t i = 0; i < m; ++i) {
      pivot = a[i] - x - (i > 0 ? b[i - 1] * b[i - 1] / pivot : 0.0);
      if (pivot == 0.0) pivot = -1e-300;
      if (pivot < 0.0) ++count;
    }
    return count;
  };
  for (int it = 0; it < 200 && high - low > 1e-15 * std::max(std::abs(low), std::abs(high)); ++it) {
    const double middle = 0.5 * (low + high);
    if (below(middle) == m) high = middle;
    else low = middle;
  }
  return high;
}

}  // namespace

double estimate_stable_time_step(const Model& model, const Assembler& assembler, int iterations) {
  const int n = model.free_dof_count();
  const auto& free = model.free_dofs();
  if (n == 0) return INFINITY;
  // K q is a central difference of the internal forces about rest, with
  // displacements of 1e-7 of the mesh's size: no tangent is assembled, so an
  // explicit run never holds one (a tangent is 12 bytes a non-zero).
  const auto& rest = model.mesh().rest_positions;
  double size = 0.0;
  for (int axis = 0; axis < 3; ++axis) {
    double low = INFINITY, high = -INFINITY;
    for (std::size_t i = axis; i < rest.size(); i += 3) low = std::min(low, rest[i]), high = std::max(high, rest[i]);
    if (high > low) size = std::max(size, high - low);
  }
  if (size == 0.0) size = 1.0;
  const detail::StateRows rows(assembler);
  std::vector<double> inverse_sqrt_mass(n);
  for (int i = 0; i < n; ++i) inverse_sqrt_mass[i] = 1.0 / std::sqrt(model.lumped_mass()[free[i]]);
  std::vector<double> u(model.dof_count(), 0.0), g_plus(model.dof_count()), g_minus(model.dof_count());
  // y = M^-1/2 K M^-1/2 q over the free dofs.
  // With a divided state only this rank's rows of q, w and y are computed.
  std::vector<double> scaled(n);
  const auto apply = [&](const std::vector<double>& q, std::vector<double>& y) {
    for (int i = 0; i < n; ++i) scaled[i] = inverse_sqrt_mass[i] * q[i];
    const double h = 1e-7 * size / rows.max_abs_free(scaled);
    for (int i = 0; i < n; ++i) u[free[i]] = h * scaled[i];
    rows.share_ghost_dofs(u);
    assembler.assemble(u, g_plus, nullptr);
    for (int i = 0; i < n; ++i) u[free[i]] = -u[free[i]];
    assembler.assemble(u, g_minus, nullptr);
    for (int i = 0; i < n; ++i) y[i] = inverse_sqrt_mass[i] * (g_plus[free[i]] - g_minus[free[i]]) / (2.0 * h);
  };
  // Lanczos from a fixed, non-special start vector (deterministic, the
  // same over any number of ranks): its largest Ritz value approaches
  // omega_max^2 from below, far faster than power iterations.
  std::vector<double> q(n), previous(n, 0.0), w(n), alpha, beta;
  for (int i = 0; i < n; ++i) q[i] = 1.0 + 0.5 * std::sin(1.0 + 12.9898 * rows.whole_free_row(i));
  const double start = rows.norm_free(q);
  for (double& value : q) value /= start;
  double lambda = 0.0, coupling = 0.0;
  for (int it = 0; it < iterations; ++it) {
    apply(q, w);
    for (int i = 0; i < n; ++i) w[i] -= coupling * previous[i];
    alpha.push_back(rows.dot_free(q, w));
    for (int i = 0; i < n; ++i) w[i] -= alpha.back() * q[i];
    const double estimate = largest_tridiagonal_eigenvalue(alpha, beta);
    const bool settled = it > 0 && estimate - lambda <= 1e-8 * estimate;
    lambda = estimate;
    coupling = rows.norm_free(w);
    if (settled || coupling <= 1e-12 * std::abs(lambda)) break;
    beta.push_back(coupling);
    previous.swap(q);
    for (int i = 0; i < n; ++i) q[i] = w[i] / coupling;
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
  for (const int d : run.model.free_dofs()) {
    if (free_ranges_.empty() || free_ranges_.back().second != d) free_ranges_.emplace_back(d, d);
    ++free_ranges_.back().second;
  }
}

// v += dt (M^-1 (f - g) - alpha v), u += dt v. With the state on one process
// the loop runs over contiguous ranges of free dofs: it vectorises, where
// the loop through the free-dof list (a gather, a division and a branch per
// dof) was a visible share of a folded Hooke step. The arithmetic per dof is
// the same, so are the results.
bool ExplicitIntegrator::advance_free_dofs(State& state, double load_factor) const {
  const Model& model = run_.model;
  const double dt = run_.settings.dt, alpha = run_.settings.damping_mass;
  const double* gravity = model.gravity_load().data();
  const double* surface = model.surface_load().data();
  const double* mass = model.lumped_mass().data();
  const double* g = g_.data();
  double* u = state.displacement.data();
  double* v = state.velocity.data();
  const auto advance = [&](int d) {
    v[d] += dt * ((load_factor * (gravity[d] + surface[d]) - g[d]) / mass[d] - alpha * v[d]);
    u[d] += dt * v[d];
  };
  const detail::StateRows rows(run_.assembler);
  double check = 0.0;  // 0 while every u is finite, NaN after an infinity or a NaN
  if (rows.divided()) {
    const auto& free = model.free_dofs();
    rows.for_each_free([&](int i) {
      advance(free[i]);
      check += 0.0 * u[free[i]];
    });
  } else {
    for (const std::pair<int, int>& range : free_ranges_) {
      // Plain ints: clang 14 cannot refer to structured bindings inside an OpenMP construct.
      const int first = range.first, last = range.second;
#pragma omp simd reduction(+ : check)
      for (int d = first; d < last; ++d) {
        advance(d);
        check += 0.0 * u[d];
      }
    }
  }
  return check == 0.0;
}

void ExplicitIntegrator::step(State& state, const StepObserver& observer) {
  Integration& run = run_;
  const Model& model = run.model;
  const SolverSettings& settings = run.settings;
  const double dt = settings.dt;
  const int dofs = model.dof_count();
  state.displacement.resize(dofs, 0.0);
  state.velocity.resize(dofs, 0.0);
  g_.resize(dofs);
  const int s = state.step + 1;
  const auto start = std::chrono::steady_clock::now();
  const double t = state.time, t1 = t + dt;
  auto& u = state.displacement;
  auto& v = state.velocity;
  // The viscous history steps from t - dt to t here, with the force at u(t).
  run.assembler.begin_viscous_step(state.viscous_history, dt);
  detail::assemble(run, u, g_, nullptr);
  if (!run.assembler.viscous_part().empty()) run.assembler.commit_viscous_step(u, state.viscous_history);
  // One pass over the free dofs (the step's vector work is a visible share
  // of a folded Hooke step): external force at t, velocity, position.
  const bool finite = advance_free_dofs(state, model.load_factor(t));
  const detail::StateRows rows(run.assembler);
  // Constrained dofs follow their prescribed path.
  for (const PrescribedDof& p : model.prescribed()) {
    const double next = model.prescribed_value(p, t1);
    v[p.dof] = (next - u[p.dof]) / dt;
    u[p.dof] = next;
  }
  if (!rows.on_every_rank(finite))
    throw NumericalError("the displacement in step " + std::to_string(s) + " (t = " + std::to_string(t1) +
                         " s) is not finite (NaN or infinity)");
  rows.share_ghost_dofs(u, v);
  state.time = t1;
  state.step = s;
  run.statistics.newton_per_step.push_back(0);
  run.statistics.step_ms.push_back(1e3 * detail::seconds_since(start));
  if (observer) observer(state);
}

void ExplicitIntegrator::finish(const State& state) {
  detail::require_no_inversion(run_.assembler, state.displacement, "at the end of the explicit run");
}

void solve_explicit(Integration& run, State& state, const StepObserver& observer) {
  ExplicitIntegrator integrator(run);
  integrator.run(state, observer);
}

}  // namespace tensormass
