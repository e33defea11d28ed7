// Explicit solver (explicit_solver.cpp): energy conservation without
// damping, the stable time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "integrate.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {
namespace {

using test::integrate;

TEST(ExplicitSolver, ConservesEnergyWithoutDamping) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("stvk", SolverType::explicit_euler);
  scene.model.materials[0].young = 1e9;  // 1 cm deflection: a clean oscillation
  const Model model(mesh, scene.model);
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
  Scene scene = test::cantilever("hooke", SolverType::explicit_euler);
  const Model model(mesh, scene.model);
  scene.solver.dt = 3 * estimate_stable_time_step(model, Assembler(model));
  scene.solver.steps = 2000;
  SolveStatistics statistics;
  EXPECT_THROW(integrate(mesh, scene, statistics), NumericalError);
  ASSERT_EQ(statistics.warnings.size(), 1u);
  EXPECT_NE(statistics.warnings[0].find("stable time step"), std::string::npos);
}

}  // namespace
}  // namespace tensormass
