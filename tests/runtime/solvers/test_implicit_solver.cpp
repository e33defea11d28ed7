// Implicit solver (implicit_solver.cpp): stability far above the explicit
// limit, CHOLMOD and CG agree, thread independence, prescribed motion.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "integrate.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {
namespace {

using test::integrate;
using test::tip_deflection;

TEST(ImplicitSolver, StableAtAHundredTimesTheExplicitLimit) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("stvk", SolverType::implicit_euler);
  const Model model(mesh, scene.model);
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
  Scene scene = test::cantilever("stvk", SolverType::implicit_euler);
  scene.solver.dt = 0.01;
  scene.solver.steps = 5;
  scene.solver.newton_iterations = 2;
  SolveStatistics direct_statistics, cg_statistics;
  const State direct = integrate(mesh, scene, direct_statistics);
  scene.solver.linear.type = LinearSolverType::cg;
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
  Scene scene = test::cantilever("stvk", SolverType::implicit_euler);
  scene.solver.dt = 0.01;
  scene.solver.steps = 3;
  scene.solver.newton_iterations = 2;
  scene.solver.linear.type = LinearSolverType::cg;
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
  Scene scene = test::cantilever("hooke", SolverType::implicit_euler);
  scene.model.loads.gravity = {0, 0, 0};
  PrescribedSpec lift;
  lift.region = "tip";
  lift.displacement = {0, 0.05, 0};
  lift.components = {false, true, false};
  lift.profile.kind = tensormass::ProfileKind::sinusoid;
  lift.profile.period = 1.0;
  scene.model.prescribed = {lift};
  scene.solver.dt = 0.05;
  scene.solver.steps = 10;  // half a period: the full amplitude
  SolveStatistics statistics;
  const State state = integrate(mesh, scene, statistics);
  for (int node : mesh.group("tip")->nodes) EXPECT_NEAR(state.displacement[node * 2 + 1], 0.05, 1e-12);
}

}  // namespace
}  // namespace tensormass
