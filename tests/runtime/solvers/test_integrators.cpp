// Static, implicit and explicit integration on small beams.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>

#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/solvers/integrators.hpp"
#include "tensormass/solvers/linear_solver.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// Runs one integrator on `mesh` and returns the final state.
State integrate(const Mesh& mesh, const Scene& scene, SolveStatistics& statistics,
                const StepObserver& observer = {}) {
  const Model model(mesh, scene);
  const Assembler assembler(model);
  auto linear = make_linear_solver(scene.solver.linear);
  Integration run{model, assembler, *linear, scene, statistics};
  State state;
  if (scene.solver.type == "static") solve_static(run, state, observer);
  else if (scene.solver.type == "implicit") solve_implicit(run, state, observer);
  else solve_explicit(run, state, observer);
  return state;
}

double tip_deflection(const Mesh& mesh, const State& state) {
  double sum = 0;
  const Group& tip = *mesh.group("tip");
  for (int node : tip.nodes) sum += state.displacement[node * mesh.dim + 1];
  return sum / tip.nodes.size();
}

TEST(StaticSolver, HookeCantileverMatchesBeamTheoryInOneSolve) {
  // 10 x 1 beam under gravity: Euler-Bernoulli w = q L^4 / (8 E I), plane
  // strain E' = E / (1 - nu^2); quad8 elements bend without locking.
  const Mesh mesh = test::beam(2, "quad4", {40, 4, 1}, 2);
  Scene scene = test::cantilever("hooke");
  scene.materials[0].young = 1e9;
  SolveStatistics statistics;
  const State state = integrate(mesh, scene, statistics);
  const double length = 10, q = 1000 * 9.81 * 1.0, inertia = 1.0 / 12, young = 1e9 / (1 - 0.09);
  const double theory = -q * std::pow(length, 4) / (8 * young * inertia);
  EXPECT_NEAR(tip_deflection(mesh, state) / theory, 1.0, 0.02);
  // One solve, plus at most one more that finds the residual at round-off.
  EXPECT_LE(statistics.newton_iterations, 2);
}

TEST(StaticSolver, StvkConvergesAtLargeDeflectionAndDiffersFromHooke) {
  const Mesh mesh = test::beam(2, "quad4", {20, 4, 1});
  Scene scene = test::cantilever("stvk");
  scene.materials[0].young = 3e6;
  scene.solver.load_steps = 4;
  SolveStatistics stvk_statistics, hooke_statistics;
  const State stvk = integrate(mesh, scene, stvk_statistics);
  scene.materials[0].law = "hooke";
  const State hooke = integrate(mesh, scene, hooke_statistics);
  EXPECT_GT(std::abs(tip_deflection(mesh, hooke)), 0.1 * 5);  // beyond small displacements
  EXPECT_LT(std::abs(tip_deflection(mesh, stvk)), std::abs(tip_deflection(mesh, hooke)));
  EXPECT_EQ(stvk_statistics.newton_per_step.size(), 4u);
}

TEST(StaticSolver, NewtonFailureIsANumericalError) {
  const Mesh mesh = test::beam(2, "quad4", {20, 4, 1});
  Scene scene = test::cantilever("stvk");
  scene.materials[0].young = 1e5;
  scene.solver.max_iterations = 2;
  SolveStatistics statistics;
  EXPECT_THROW(integrate(mesh, scene, statistics), NumericalError);
}

TEST(ExplicitSolver, ConservesEnergyWithoutDamping) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("stvk", "explicit");
  scene.materials[0].young = 1e9;  // 1 cm deflection: a clean oscillation
  const Model model(mesh, scene);
  const double stable = estimate_stable_time_step(model, Assembler(model));
  scene.solver.dt = 0.2 * stable;
  scene.solver.steps = 4000;
  const std::vector<double> f = external_force(model, 1.0);
  double first = NAN, worst = 0, largest_strain = 0;
  SolveStatistics statistics;
  integrate(mesh, scene, statistics, [&](const State& state) {
    double kinetic = 0, work = 0;
    for (int d = 0; d < model.dof_count(); ++d) {
      kinetic += 0.5 * model.lumped_mass()[d] * state.velocity[d] * state.velocity[d];
      work += f[d] * state.displacement[d];
    }
    const double strain = model.strain_energy(state.displacement);
    const double total = kinetic + strain - work;
    if (std::isnan(first)) first = total;
    worst = std::max(worst, std::abs(total - first));
    largest_strain = std::max(largest_strain, strain);
    return false;
  });
  EXPECT_GT(largest_strain, 0.0);
  EXPECT_LT(worst, 0.01 * largest_strain);
  EXPECT_TRUE(statistics.warnings.empty());
}

TEST(ExplicitSolver, WarnsAndFailsAboveTheStableStep) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("hooke", "explicit");
  const Model model(mesh, scene);
  scene.solver.dt = 3 * estimate_stable_time_step(model, Assembler(model));
  scene.solver.steps = 2000;
  SolveStatistics statistics;
  EXPECT_THROW(integrate(mesh, scene, statistics), NumericalError);
  ASSERT_EQ(statistics.warnings.size(), 1u);
  EXPECT_NE(statistics.warnings[0].find("stable time step"), std::string::npos);
}

TEST(ImplicitSolver, StableAtAHundredTimesTheExplicitLimit) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("stvk", "implicit");
  const Model model(mesh, scene);
  scene.solver.dt = 100 * estimate_stable_time_step(model, Assembler(model));
  scene.solver.steps = 200;
  scene.solver.newton_iterations = 3;
  SolveStatistics statistics;
  double largest = 0;
  const State state = integrate(mesh, scene, statistics, [&](const State& s) {
    largest = std::max(largest, std::abs(tip_deflection(mesh, s)));
    return false;
  });
  Scene statics = test::cantilever("stvk");
  SolveStatistics static_statistics;
  const double equilibrium = tip_deflection(mesh, integrate(mesh, statics, static_statistics));
  // Backward Euler dissipates: bounded by the dynamic overshoot (2x static)
  // and settling on the static solution.
  EXPECT_LT(largest, 2.0 * std::abs(equilibrium) * 1.01);
  EXPECT_NEAR(tip_deflection(mesh, state), equilibrium, 0.02 * std::abs(equilibrium));
}

TEST(ImplicitSolver, CholmodAndConjugateGradientsAgree) {
  const Mesh mesh = test::beam(3, "hex8", {8, 2, 2});
  Scene scene = test::cantilever("stvk", "implicit");
  scene.solver.dt = 0.01;
  scene.solver.steps = 5;
  scene.solver.newton_iterations = 2;
  SolveStatistics direct_statistics, cg_statistics;
  const State direct = integrate(mesh, scene, direct_statistics);
  scene.solver.linear.type = "cg";
  scene.solver.linear.tolerance = 1e-12;
  const State iterative = integrate(mesh, scene, cg_statistics);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < direct.displacement.size(); ++i) {
    worst = std::max(worst, std::abs(direct.displacement[i] - iterative.displacement[i]));
    scale = std::max(scale, std::abs(direct.displacement[i]));
  }
  EXPECT_LT(worst, 1e-8 * scale);
  EXPECT_GT(cg_statistics.linear_iterations, direct_statistics.linear_iterations);
}

TEST(ImplicitSolver, OneAndTwoThreadsAgree) {
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  Scene scene = test::cantilever("stvk", "implicit");
  scene.solver.dt = 0.01;
  scene.solver.steps = 3;
  scene.solver.newton_iterations = 2;
  scene.solver.linear.type = "cg";
  scene.solver.linear.tolerance = 1e-12;
  const int threads = omp_get_max_threads();
  SolveStatistics s1, s2;
  omp_set_num_threads(1);
  const State one = integrate(mesh, scene, s1);
  omp_set_num_threads(2);
  const State two = integrate(mesh, scene, s2);
  omp_set_num_threads(threads);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < one.displacement.size(); ++i) {
    worst = std::max(worst, std::abs(one.displacement[i] - two.displacement[i]));
    scale = std::max(scale, std::abs(one.displacement[i]));
  }
  EXPECT_LE(worst, 1e-12 * scale);
}

TEST(ImplicitSolver, PrescribedSinusoidMovesTheGroup) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("hooke", "implicit");
  scene.loads.gravity = {0, 0, 0};
  PrescribedSpec lift;
  lift.region = "tip";
  lift.displacement = {0, 0.05, 0};
  lift.components = {false, true, false};
  lift.profile.kind = "sinusoid";
  lift.profile.period = 1.0;
  scene.prescribed = {lift};
  scene.solver.dt = 0.05;
  scene.solver.steps = 10;  // half a period: the full amplitude
  SolveStatistics statistics;
  const State state = integrate(mesh, scene, statistics);
  for (int node : mesh.group("tip")->nodes) EXPECT_NEAR(state.displacement[node * 2 + 1], 0.05, 1e-12);
}

}  // namespace
}  // namespace tensormass
