// Explicit solver (explicit_solver.cpp): energy conservation without
// damping, the stable time step.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include "support/integrate.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {
namespace {

using test::integrate;

/// The largest eigenvalue of the dense symmetric matrix a (n by n, row
/// major) by cyclic Jacobi rotations: the reference for the estimate.
double largest_eigenvalue(std::vector<double> a, int n) {
  for (int sweep = 0; sweep < 100; ++sweep) {
    double off = 0.0;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) off += a[p * n + q] * a[p * n + q];
    if (off < 1e-30) break;
    for (int p = 0; p < n; ++p)
      for (int q = p + 1; q < n; ++q) {
        if (a[p * n + q] == 0.0) continue;
        const double theta = (a[q * n + q] - a[p * n + p]) / (2.0 * a[p * n + q]);
        const double t = (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < n; ++k) {  // columns p and q
          const double kp = a[k * n + p], kq = a[k * n + q];
          a[k * n + p] = c * kp - s * kq, a[k * n + q] = s * kp + c * kq;
        }
        for (int k = 0; k < n; ++k) {  // rows p and q
          const double pk = a[p * n + k], qk = a[q * n + k];
          a[p * n + k] = c * pk - s * qk, a[q * n + k] = s * pk + c * qk;
        }
      }
  }
  double largest = -INFINITY;
  for (int i = 0; i < n; ++i) largest = std::max(largest, a[i * n + i]);
  return largest;
}

// The matrix-free Lanczos estimate against the largest eigenvalue of the
// assembled M^-1/2 K M^-1/2 at rest, on a linear and two non-linear laws,
// and on the mean-dilatation (fbar) and nodal-pressure (anp) splits near
// incompressibility.
TEST(ExplicitSolver, StableStepMatchesTheAssembledTangentsLargestEigenvalue) {
  for (const auto& [dim, type, order, law, split] :
       {std::tuple{2, "quad4", 1, "hooke", ""}, std::tuple{2, "tri3", 2, "stvk", ""},
        std::tuple{3, "tet6", 1, "neohookean", ""}, std::tuple{3, "hex8", 1, "neohookean", "fbar"},
        std::tuple{2, "quad4", 1, "hooke", "fbar"}, std::tuple{3, "tet6", 1, "neohookean", "anp"},
        std::tuple{2, "tri3", 1, "hooke", "anp"}}) {
    SCOPED_TRACE(std::string(type) + " " + law + " " + split);
    const Mesh mesh =
        test::beam(dim, type, dim == 2 ? std::array<int, 3>{6, 2, 1} : std::array<int, 3>{4, 2, 2}, order);
    Scene scene = test::cantilever(law, SolverType::explicit_euler);
    scene.model.materials[0].split = split;
    if (!std::string(split).empty()) scene.model.materials[0].constants = elastic_constants(1e6, 0.499);
    const Model model(mesh, scene.model);
    const Assembler assembler(model);
    SparseMatrix K = assembler.pattern();
    std::vector<double> zero(model.dof_count(), 0.0), g(model.dof_count());
    assembler.assemble(zero, g, &K);
    const int n = model.free_dof_count();
    std::vector<double> dense(static_cast<std::size_t>(n) * n, 0.0);
    for (int r = 0; r < n; ++r)
      for (int k = K.row_start[r]; k < K.row_start[r + 1]; ++k)
        dense[r * n + K.columns[k]] = K.values[k] / std::sqrt(model.lumped_mass()[model.free_dofs()[r]] *
                                                              model.lumped_mass()[model.free_dofs()[K.columns[k]]]);
    const double exact = 2.0 / std::sqrt(largest_eigenvalue(dense, n));
    const double estimate = estimate_stable_time_step(model, assembler);
    EXPECT_GE(estimate, exact * (1 - 1e-9));  // Ritz values approach from below
    EXPECT_NEAR(estimate, exact, 1e-6 * exact);
  }
}

TEST(ExplicitSolver, ConservesEnergyWithoutDamping) {
  const Mesh mesh = test::beam(2, "quad4", {10, 2, 1});
  Scene scene = test::cantilever("stvk", SolverType::explicit_euler);
  scene.model.materials[0].constants["young"] = 1e9;  // 1 cm deflection: a clean oscillation
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
