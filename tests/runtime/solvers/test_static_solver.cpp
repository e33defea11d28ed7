// Static solver (static_solver.cpp): Hooke against beam theory in one
// solve, StVK at large deflection, Newton failure.
#include <gtest/gtest.h>

#include <cmath>

#include "integrate.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {
namespace {

using test::integrate;
using test::tip_deflection;

TEST(StaticSolver, HookeCantileverMatchesBeamTheoryInOneSolve) {
  // 10 x 1 beam under gravity: Euler-Bernoulli w = q L^4 / (8 E I), plane
  // strain E' = E / (1 - nu^2); quad8 elements bend without locking.
  const Mesh mesh = test::beam(2, "quad4", {40, 4, 1}, 2);
  Scene scene = test::cantilever("hooke");
  scene.model.materials[0].young = 1e9;
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
  scene.model.materials[0].young = 3e6;
  scene.solver.load_steps = 4;
  SolveStatistics stvk_statistics, hooke_statistics;
  const State stvk = integrate(mesh, scene, stvk_statistics);
  scene.model.materials[0].law = "hooke";
  const State hooke = integrate(mesh, scene, hooke_statistics);
  EXPECT_GT(std::abs(tip_deflection(mesh, hooke)), 0.1 * 5);  // beyond small displacements
  EXPECT_LT(std::abs(tip_deflection(mesh, stvk)), std::abs(tip_deflection(mesh, hooke)));
  EXPECT_EQ(stvk_statistics.newton_per_step.size(), 4u);
}

TEST(StaticSolver, NewtonFailureIsANumericalError) {
  const Mesh mesh = test::beam(2, "quad4", {20, 4, 1});
  Scene scene = test::cantilever("stvk");
  scene.model.materials[0].young = 1e5;
  scene.solver.max_iterations = 2;
  SolveStatistics statistics;
  EXPECT_THROW(integrate(mesh, scene, statistics), NumericalError);
}

}  // namespace
}  // namespace tensormass
