// Implicit solver (implicit_solver.cpp): stability far above the explicit
// limit, CHOLMOD and CG agree, thread independence, prescribed motion; large
// deformation: indentation, a cube pressed to 30 % and released, the line
// search and the message naming an inverted cell and its law.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "support/integrate.hpp"
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

namespace tensormass {
namespace {

/// A 10 x 5 x 10 cm soft block (E 5 kPa, nu 0.45, 3,000 tets) on a fixed
/// base, a 2 x 2 cm probe on its top pushed `depth` down over 0.5 s
/// (implicit, dt 0.01, 50 steps): the indentation of `tensormass bench
/// adaptive`, coarser.
struct Indentation {
  Mesh mesh;
  Scene scene;
};

Indentation indentation(const std::string& law, double depth) {
  BeamSpec spec;
  spec.dim = 3;
  spec.cells = {10, 5, 10};
  spec.size = {0.1, 0.05, 0.1};
  spec.phases = {{"tet6", 1.0}};
  Indentation c{make_beam(spec), test::cantilever(law, SolverType::implicit_euler)};
  const double eps = 1e-9;
  c.mesh.add_node_group("base", [&](double, double y, double) { return y < eps; });
  c.mesh.add_node_group("probe", [&](double x, double y, double z) {
    return y > 0.05 - eps && std::abs(x - 0.05) <= 0.01 + eps && std::abs(z - 0.05) <= 0.01 + eps;
  });
  Scene& s = c.scene;
  s.model.materials[0].constants = elastic_constants(5e3, 0.45);
  s.model.fixed = {"base"};
  s.model.loads.gravity = {0, 0, 0};
  PrescribedSpec probe;
  probe.region = "probe";
  probe.displacement = {0.0, -depth, 0.0};
  probe.profile.kind = ProfileKind::ramp;
  probe.profile.duration = 0.5;
  s.model.prescribed = {probe};
  s.solver.dt = 0.01;
  s.solver.steps = 50;
  return c;
}

double largest_component(const std::vector<double>& v) {
  double largest = 0;
  for (double x : v) largest = std::max(largest, std::abs(x));
  return largest;
}

TEST(ImplicitSolver, StableNeohookeanIndentationRunsThrough) {
  Indentation c = indentation("stable_neohookean", 0.015);
  SolveStatistics statistics;
  const State state = integrate(c.mesh, c.scene, statistics);
  for (int node : c.mesh.group("probe")->nodes) EXPECT_NEAR(state.displacement[node * 3 + 1], -0.015, 1e-12);
  EXPECT_LT(largest_component(state.displacement), 0.0151);  // nothing overshoots the probe
}

TEST(ImplicitSolver, AnInvertedCellOfALawThatCannotInvertStopsTheRunNamingCellAndLaw) {
  Indentation c = indentation("stvk", 0.015);
  SolveStatistics statistics;
  try {
    integrate(c.mesh, c.scene, statistics);
    FAIL() << "StVK under the probe was expected to invert";
  } catch (const NumericalError& e) {
    EXPECT_THAT(e.what(), testing::HasSubstr("(tet4, id "));
    EXPECT_THAT(e.what(), testing::HasSubstr("inverted (det F <= 0) under law stvk in step "));
    EXPECT_THAT(e.what(), testing::HasSubstr("stable_neohookean"));
  }
}

TEST(ImplicitSolver, HooksLawNeedsNoLineSearch) {
  Indentation c = indentation("hooke", 0.015);
  SolveStatistics statistics;
  integrate(c.mesh, c.scene, statistics);
  EXPECT_EQ(statistics.shortened_steps, 0);  // a quadratic potential: the Newton step is its minimum
}

/// A unit cube (384 tets) with its base fixed, its top pressed to 30 % of
/// the height and back by a sinusoid over 2 s (implicit, one Newton
/// iteration per 0.02 s step), stable neo-Hookean.
struct CubePress {
  Mesh mesh = test::beam(3, "tet6", {4, 4, 4});
  Scene scene = test::cantilever("stable_neohookean", SolverType::implicit_euler);
  CubePress() {
    mesh.add_node_group("top", [](double, double y, double) { return y > 1 - 1e-9; });
    mesh.add_node_group("bottom", [](double, double y, double) { return y < 1e-9; });
    scene.model.fixed = {"bottom"};
    scene.model.loads.gravity = {0, 0, 0};
    PrescribedSpec press;
    press.region = "top";
    press.displacement = {0.0, -0.7, 0.0};
    press.profile.kind = ProfileKind::sinusoid;
    press.profile.period = 2.0;
    scene.model.prescribed = {press};
    scene.solver.dt = 0.02;
    scene.solver.steps = 100;
    scene.solver.damping_mass = 5.0;
  }
};

TEST(ImplicitSolver, CubeCompressedTo30PercentAndReleasedReturnsToRest) {
  CubePress press;
  press.scene.solver.project_hessian = true;
  SolveStatistics statistics;
  double lowest = 0;
  State state = integrate(press.mesh, press.scene, statistics, [&](const State& s) {
    for (int node : press.mesh.group("top")->nodes) lowest = std::min(lowest, s.displacement[node * 3 + 1]);
    return false;
  });
  EXPECT_NEAR(lowest, -0.7, 1e-12);
  // Released: the top held where it started for one more second.
  press.scene.model.prescribed[0].profile.kind = ProfileKind::constant;
  press.scene.model.prescribed[0].displacement = {0, 0, 0};
  press.scene.solver.steps = state.step + 50;  // the integrator continues from state.step
  const Model model(press.mesh, press.scene.model);
  Assembler assembler(model);
  assembler.set_hessian_projection(true);
  auto linear = make_linear_solver(press.scene.solver.linear);
  Integration run{model, assembler, *linear, press.scene.solver, statistics};
  solve_implicit(run, state, {});
  EXPECT_LT(largest_component(state.displacement), 1e-9);
}

TEST(ImplicitSolver, WithoutProjectionTheLineSearchShortensStepsOfTheCompressedCube) {
  CubePress press;
  // To the deepest point (30 %); on the way back the unprojected linearised
  // steps tangle this coarse cube (measured from step 65 on).
  press.scene.solver.steps = 50;
  SolveStatistics statistics;
  const State state = integrate(press.mesh, press.scene, statistics);
  EXPECT_GT(statistics.shortened_steps, 0);  // first at step 43 (67 % pressed)
  EXPECT_LT(largest_component(state.displacement), 1.0);
}

}  // namespace
}  // namespace tensormass
