// Backward Euler: M (v1 - v0) / dt = f(t1) - g(u1) - C v1, u1 = u0 + dt v1,
// with Rayleigh damping C = alpha M + beta K(u). Newton on u1 starting from
// the predictor u0 + dt v0 (solver.predictor), so one iteration is the
// classic linearised step (Baraff-Witkin) from there; each Newton step is
// shortened by a backtracking line search on the step's incremental
// potential when the full step would raise it or invert a cell.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "integrators/integration_support.hpp"
#include "integrators/integrator_kinds.hpp"

namespace tensormass {

namespace {

/// One backward Euler step from (u0, v0) to time t1: its residual and the
/// incremental potential whose gradient it is,
///   Phi(u) = sum_free m/2 (|u - u0 - dt v0|^2 / dt^2 + alpha |u - u0|^2 / dt)
///            + W(u) - f.u + beta / (2 dt) du.K du,   du = (u - u0) on the free dofs.
/// K is the tangent at the current Newton iterate, held fixed along a line
/// search, so that Phi's slope there is the residual's (Rayleigh stiffness
/// damping of a non-linear K has no potential of its own).
struct EulerStep {
  Integration& run;
  const std::vector<double>& u0;
  const std::vector<double>& v0;
  const std::vector<double>& f;  ///< external force at t1 (dof_count)
  const detail::StateRows& rows;

  int free_count() const { return run.model.free_dof_count(); }
  /// Scratch vectors over the free dofs, sized once (the Newton loop allocates nothing).
  mutable std::vector<double> scratch_a, scratch_b;

  /// r (free dofs) = M ((v - v0) / dt + alpha v) + beta K v + g - f, v = (u - u0) / dt.
  void residual(const std::vector<double>& u, const std::vector<double>& g, const SparseMatrix& K,
                std::vector<double>& r) const {
    const SolverSettings& s = run.settings;
    const auto& free = run.model.free_dofs();
    const auto& mass = run.model.lumped_mass();
    const int n = free_count();
    std::vector<double>& v_free = scratch_a;
    std::vector<double>& kv = scratch_b;
    v_free.resize(n), kv.assign(n, 0.0);
    for (int i = 0; i < n; ++i) v_free[i] = (u[free[i]] - u0[free[i]]) / s.dt;
    if (s.damping_stiffness != 0.0) run.assembler.tangent_product(K, v_free, kv);
    rows.for_each_free([&](int i) {
      const int d = free[i];
      r[i] = mass[d] * ((v_free[i] - v0[d]) / s.dt + s.damping_mass * v_free[i]) + s.damping_stiffness * kv[i] + g[d] -
             f[d];
    });
  }

  /// Phi(u) with K the tangent of the current iterate.
  double potential(const std::vector<double>& u, const SparseMatrix& K) const {
    const SolverSettings& s = run.settings;
    const auto& free = run.model.free_dofs();
    const auto& mass = run.model.lumped_mass();
    const int n = free_count();
    double inertia = 0.0, external = 0.0;
    std::vector<double>& du = scratch_a;
    std::vector<double>& kdu = scratch_b;
    du.resize(n), kdu.assign(n, 0.0);
    for (int i = 0; i < n; ++i) du[i] = u[free[i]] - u0[free[i]];
    rows.for_each_free([&](int i) {
      const int d = free[i];
      const double ahead = du[i] - s.dt * v0[d];
      inertia += 0.5 * mass[d] * (ahead * ahead / (s.dt * s.dt) + s.damping_mass * du[i] * du[i] / s.dt);
      external += f[d] * u[d];
    });
    if (rows.divided()) inertia = parallel::sum_over_ranks(inertia), external = parallel::sum_over_ranks(external);
    double damping = 0.0;
    if (s.damping_stiffness != 0.0) {
      run.assembler.tangent_product(K, du, kdu);
      damping = 0.5 * s.damping_stiffness / s.dt * rows.dot_free(du, kdu);
    }
    double energy = 0.0;
    {
      detail::PhaseTimer timer(run.statistics.assembly_seconds);
      energy = run.assembler.energy(u);
    }
    return inertia + energy - external + damping;
  }
};

/// The start of the step's Newton iterations: u0 + dt v0 on the free dofs
/// (solver.predictor: velocity) unless that inverts a cell, else u0; the
/// prescribed dofs at their values at t1.
std::vector<double> predict(const EulerStep& step, double t1) {
  const Model& model = step.run.model;
  std::vector<double> u = step.u0;
  model.apply_constraints(t1, u);
  if (step.run.settings.predictor == StepPredictor::none) return u;
  std::vector<double> ahead = u;
  for (int d : model.free_dofs()) ahead[d] += step.run.settings.dt * step.v0[d];
  return detail::any_cell_inverted(step.run.assembler, ahead) ? u : ahead;
}

/// What a line search did: the step length taken, and whether the new u
/// was checked free of inverted cells.
struct SearchResult {
  double length = 1.0;
  bool uninverted = false;
};

/// Moves u along `direction` (free dofs): the full step unless it raises
/// Phi by Armijo's test (slope: r.direction, negative for descent) or
/// inverts a cell of a law that cannot invert; then halved, at most 10
/// times. When no length passes, the full step is taken (the step's
/// inversion check then names the cell).
SearchResult line_search(const EulerStep& step, const SparseMatrix& K, double slope,
                         const std::vector<double>& direction, std::vector<double>& u) {
  const Model& model = step.run.model;
  const auto& free = model.free_dofs();
  const double start = step.potential(u, K);
  // Each cell's energy carries a round-off of about 1e-16 of E times its
  // volume whatever its value (its terms cancel near rest), and so does
  // the total: changes below that say nothing about descent.
  const double noise = 1e-12 * std::abs(start) + 1e-14 * model.energy_scale();
  std::vector<double> trial(u.size());
  auto move = [&](double length) {
    trial = u;
    for (std::size_t i = 0; i < free.size(); ++i) trial[free[i]] += length * direction[i];
  };
  double length = 1.0;
  for (int halving = 0; halving <= 10; ++halving, length *= 0.5) {
    move(length);
    if (detail::any_cell_inverted(step.run.assembler, trial)) continue;
    if (!(slope < 0)) break;  // not a descent direction: only the inversion guard applies
    const double energy = step.potential(trial, K);
    if (std::isfinite(energy) && energy <= start + 1e-4 * length * slope + noise) break;
  }
  const bool found = length >= 1.0 / 1024;
  if (!found) move(1.0);
  u.swap(trial);
  return {found ? length : 1.0, found};
}

}  // namespace

// Without stiffness damping nothing reads K once J is formed (the residual
// and the line search's potential use it only for beta K v), so J is built
// in K's storage: one copy of the tangent less.
ImplicitIntegrator::ImplicitIntegrator(Integration& run)
    : Integrator(run), K_(run.assembler.pattern()), J_(run.settings.damping_stiffness != 0.0 ? K_ : SparseMatrix{}) {}

void ImplicitIntegrator::step(State& state, const StepObserver& observer) {
  Integration& run = run_;
  const Model& model = run.model;
  const SolverSettings& settings = run.settings;
  const double dt = settings.dt, alpha = settings.damping_mass, beta = settings.damping_stiffness;
  const int n = model.free_dof_count(), dofs = model.dof_count();
  const auto& free = model.free_dofs();
  const auto& mass = model.lumped_mass();
  state.displacement.resize(dofs, 0.0);
  state.velocity.resize(dofs, 0.0);
  g_.resize(dofs), v_.resize(dofs), r_.resize(n);
  std::vector<double>& direction = state.warm_start;
  direction.resize(n, 0.0);
  const double mass_factor = 1.0 / (dt * dt) + alpha / dt, stiffness_factor = 1.0 + beta / dt;
  const int s = state.step + 1;
  const auto start = std::chrono::steady_clock::now();
  const double t1 = state.time + dt;
  const std::string where = "in step " + std::to_string(s) + " (t = " + std::to_string(t1) + " s)";
  const std::vector<double> u0 = state.displacement, v0 = state.velocity;
  const std::vector<double> f = external_force(model, model.load_factor(t1));
  const detail::StateRows rows(run.assembler);
  const EulerStep step{run, u0, v0, f, rows, {}, {}};
  run.assembler.begin_viscous_step(state.viscous_history, dt);
  std::vector<double> u = predict(step, t1);
  double reference = 0.0;
  int iterations = 0;
  bool uninverted = false;  // u checked by the last line search
  for (int iteration = 1; iteration <= settings.newton_iterations; ++iteration) {
    detail::assemble(run, u, g_, &K_);
    step.residual(u, g_, K_, r_);
    const double residual = rows.norm_free(r_);
    if (!std::isfinite(residual)) throw NumericalError("the residual " + where + " is not finite (NaN or infinity)");
    if (iteration == 1) reference = std::max(residual, 1e-300);
    else if (residual <= settings.tolerance * reference) break;
    // J = (1/dt^2 + alpha/dt) M + (1 + beta/dt) K, in K's storage when beta = 0 (K is not read again)
    SparseMatrix& J = beta != 0.0 ? J_ : K_;
    if (beta != 0.0)
      for (int k = 0; k < K_.nonzeros(); ++k) J_.values[k] = stiffness_factor * K_.values[k];
    for (int i = 0; i < n; ++i)  // rows of other MPI ranks are empty here
      if (J.diagonal[i] >= 0) J.values[J.diagonal[i]] += mass_factor * mass[free[i]];
    for (double& x : r_) x = -x;
    detail::linear_solve(run, J, r_, direction);  // warm start: the previous correction
    rows.share_ghost_free(direction);
    const double slope = -rows.dot_free(r_, direction);  // r holds -residual here
    const SearchResult search = line_search(step, K_, slope, direction, u);
    if (search.length < 1.0) ++run.statistics.shortened_steps;
    uninverted = search.uninverted;
    iterations = iteration;
  }
  detail::require_finite(rows, u, "the displacement " + where);
  if (!uninverted) detail::require_no_inversion(run.assembler, u, where);
  for (int d = 0; d < dofs; ++d) v_[d] = (u[d] - u0[d]) / dt;
  if (!run.assembler.viscous_part().empty()) run.assembler.commit_viscous_step(u, state.viscous_history);
  state.displacement = std::move(u);
  state.velocity = v_;
  state.time = t1;
  state.step = s;
  run.statistics.newton_iterations += iterations;
  run.statistics.newton_per_step.push_back(iterations);
  run.statistics.step_ms.push_back(1e3 * detail::seconds_since(start));
  if (observer) observer(state);
}

void solve_implicit(Integration& run, State& state, const StepObserver& observer) {
  ImplicitIntegrator integrator(run);
  integrator.run(state, observer);
}

}  // namespace tensormass
