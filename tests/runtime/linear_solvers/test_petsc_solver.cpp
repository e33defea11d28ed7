// solver.linear.type: petsc (petsc_solver.cpp): PETSc's CG + GAMG reaches
// the requested tolerance, reuses its preconditioner for a drifted matrix
// and rebuilds it once that stops paying, uses the rigid-body modes of the
// free nodes, gives implicit and static runs that agree with CHOLMOD, and
// turns bad options and a solve that does not converge into clear errors;
// where CG breaks down (an indefinite matrix) it goes on with GMRES.
// Skipped, saying so, in a build without PETSc.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "support/integrate.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace tensormass {
namespace {

using test_support::expect_contains;

#define SKIP_WITHOUT_PETSC() \
  if (!petsc_available()) GTEST_SKIP() << "this build has no PETSc (libpetsc-real-dev)"

LinearSolverSettings petsc_settings(const std::string& options = "-ksp_type cg -pc_type gamg") {
  LinearSolverSettings settings;
  settings.type = LinearSolverType::petsc;
  settings.petsc_options = options;
  return settings;
}

/// The step matrix of a clamped 3D tet beam at rest (free dofs) and its model.
struct BeamSystem {
  Mesh mesh = test::beam(3, "tet6", {8, 2, 2});
  Scene scene = test::cantilever("stvk", SolverType::implicit_euler);
  Model model{mesh, scene.model};
  Assembler assembler{model};
  SparseMatrix K = assembler.pattern();
  std::vector<double> b;
  /// K + mass_factor M, as an implicit step's matrix with mass_factor = 1 / dt^2.
  explicit BeamSystem(double mass_factor = 1e3) {
    std::vector<double> u(model.dof_count(), 0.0), g(model.dof_count());
    assembler.assemble(u, g, &K);
    for (int i = 0; i < K.rows; ++i) K.values[K.diagonal[i]] += mass_factor * model.lumped_mass()[model.free_dofs()[i]];
    b.resize(K.rows);
    for (int i = 0; i < K.rows; ++i) b[i] = std::sin(0.3 * i) + 0.5;
  }
};

double relative_residual(const SparseMatrix& A, const std::vector<double>& b, const std::vector<double>& x) {
  std::vector<double> ax(b.size());
  A.multiply(x, ax);
  double r2 = 0, b2 = 0;
  for (std::size_t i = 0; i < b.size(); ++i) r2 += (b[i] - ax[i]) * (b[i] - ax[i]), b2 += b[i] * b[i];
  return std::sqrt(r2 / b2);
}

TEST(PetscSolver, ReachesTheToleranceAndAgreesWithCholmod) {
  SKIP_WITHOUT_PETSC();
  BeamSystem system;
  auto petsc = make_linear_solver(petsc_settings());
  auto cholmod = make_linear_solver(LinearSolverSettings{});
  std::vector<double> x(system.b.size(), 0.0), exact(system.b.size(), 0.0);
  petsc->factorize(system.K);
  const int iterations = petsc->solve(system.b, x, 1e-10);
  EXPECT_GT(iterations, 1);
  EXPECT_LE(relative_residual(system.K, system.b, x), 1e-10);
  cholmod->factorize(system.K);
  cholmod->solve(system.b, exact, 1e-10);
  double difference = 0, scale = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    difference = std::max(difference, std::abs(x[i] - exact[i])), scale = std::max(scale, std::abs(exact[i]));
  EXPECT_LE(difference, 1e-7 * scale);
  expect_contains(petsc->name(), {"petsc", "cg", "gamg"});
  // A looser tolerance takes fewer iterations (from the same start).
  std::vector<double> loose(system.b.size(), 0.0);
  EXPECT_LT(petsc->solve(system.b, loose, 1e-4), iterations);
}

TEST(PetscSolver, RigidBodyModesCutTheIterations) {
  SKIP_WITHOUT_PETSC();
  BeamSystem system;
  auto plain = make_linear_solver(petsc_settings());
  auto blocks = make_linear_solver(petsc_settings());
  describe_free_nodes(*blocks, system.model);
  std::vector<double> x(system.b.size(), 0.0), y(system.b.size(), 0.0);
  plain->factorize(system.K);
  blocks->factorize(system.K);
  const int without = plain->solve(system.b, x, 1e-10), with = blocks->solve(system.b, y, 1e-10);
  EXPECT_LE(relative_residual(system.K, system.b, y), 1e-10);
  EXPECT_LT(with, without);
}

TEST(PetscSolver, ReusesItsPreconditionerAndRebuildsItWhenItNoLongerFits) {
  SKIP_WITHOUT_PETSC();
  // A mass-dominated matrix (a short time step), then one slightly stiffer
  // relative to the mass (the preconditioner is reused: a few more
  // iterations), then one where stiffness dominates (the reused
  // preconditioner fails; it is rebuilt and the solve converges).
  BeamSystem system(1e6);
  auto solver = make_linear_solver(petsc_settings());
  describe_free_nodes(*solver, system.model);
  std::vector<double> x(system.b.size(), 0.0);
  solver->factorize(system.K);
  const int fresh = solver->solve(system.b, x, 1e-10);
  const SparseMatrix near = BeamSystem(7e5).K, far = BeamSystem(1e3).K;
  std::fill(x.begin(), x.end(), 0.0);
  solver->factorize(near);
  const int lagged = solver->solve(system.b, x, 1e-10);
  EXPECT_LE(relative_residual(near, system.b, x), 1e-10);
  EXPECT_GE(lagged, fresh);
  EXPECT_LE(lagged, 3 * fresh);
  std::fill(x.begin(), x.end(), 0.0);
  solver->factorize(far);
  solver->solve(system.b, x, 1e-10);
  EXPECT_LE(relative_residual(far, system.b, x), 1e-10);
}

TEST(PetscSolver, BadOptionsAndNonConvergenceAreClearErrors) {
  SKIP_WITHOUT_PETSC();
  try {
    make_linear_solver(petsc_settings("-ksp_type no_such_krylov"));
    FAIL() << "a bad -ksp_type was accepted";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"petsc_options", "no_such_krylov"});
  }
  BeamSystem system;
  LinearSolverSettings settings = petsc_settings("-ksp_type cg -pc_type none");
  settings.max_iterations = 2;
  auto solver = make_linear_solver(settings);
  std::vector<double> x(system.b.size(), 0.0);
  solver->factorize(system.K);
  try {
    solver->solve(system.b, x, 1e-12);
    FAIL() << "2 unpreconditioned CG iterations converged";
  } catch (const NumericalError& e) {
    expect_contains(e.what(), {"did not converge", "DIVERGED_ITS", "2 iterations"});
  }
}

// Options PETSc never looks up (a typo, or a preconditioner's option when
// another one is in use) are named once, after the first solve; the used
// ones are not.
TEST(PetscSolver, NamesTheOptionsPetscDidNotUse) {
  SKIP_WITHOUT_PETSC();
  BeamSystem system;
  auto solver =
      make_linear_solver(petsc_settings("-ksp_type cg -pc_type jacobi -ksp_rtoll 1e-3 -pc_gamg_threshold 0.01"));
  std::vector<double> x(system.b.size(), 0.0);
  solver->factorize(system.K);
  solver->solve(system.b, x, 1e-8);
  const std::vector<std::string> warnings = solver->take_warnings();
  ASSERT_EQ(warnings.size(), 1u);
  expect_contains(warnings[0], {"petsc_options", "-ksp_rtoll", "-pc_gamg_threshold", "PETSC_OPTIONS"});
  EXPECT_EQ(warnings[0].find("-ksp_type"), std::string::npos);
  solver->solve(system.b, x, 1e-8);
  EXPECT_TRUE(solver->take_warnings().empty());
  // The defaults and options in use: nothing to say.
  auto used = make_linear_solver(petsc_settings("-ksp_type cg -pc_type gamg -pc_gamg_threshold 0.01"));
  used->factorize(system.K);
  std::fill(x.begin(), x.end(), 0.0);
  used->solve(system.b, x, 1e-8);
  EXPECT_TRUE(used->take_warnings().empty());
}

TEST(PetscSolver, FallsBackToGmresWhereCgBreaksDown) {
  SKIP_WITHOUT_PETSC();
  // [[0, 1], [1, 0]] is symmetric and indefinite (eigenvalues 1 and -1):
  // from b = (1, 0), CG's first direction has p.A p = 0.
  SparseMatrix A;
  A.rows = 2;
  A.row_start = {0, 2, 4};
  A.columns = {0, 1, 0, 1};
  A.values = {0.0, 1.0, 1.0, 0.0};
  A.diagonal = {0, 3};
  auto solver = make_linear_solver(petsc_settings("-ksp_type cg -pc_type none"));
  EXPECT_NE(solver->name().find("cg"), std::string::npos) << solver->name();
  solver->factorize(A);
  const std::vector<double> b = {1.0, 0.0};
  std::vector<double> x = {0.0, 0.0};
  solver->solve(b, x, 1e-12);
  EXPECT_NEAR(x[0], 0.0, 1e-10);
  EXPECT_NEAR(x[1], 1.0, 1e-10);
  EXPECT_NE(solver->name().find("gmres"), std::string::npos) << solver->name();
}

TEST(PetscSolver, ImplicitAndStaticRunsAgreeWithCholmod) {
  SKIP_WITHOUT_PETSC();
  for (SolverType type : {SolverType::implicit_euler, SolverType::static_newton}) {
    SCOPED_TRACE(solver_type_name(type));
    const Mesh mesh = test::beam(3, "tet6", {8, 2, 2});
    Scene scene = test::cantilever("stvk", type);
    scene.model.materials[0].constants["young"] = 1e8;  // a positive definite static tangent: CG needs one
    scene.solver.load_steps = 3;
    scene.solver.steps = 10;
    scene.solver.dt = 0.01;
    SolveStatistics direct_statistics, petsc_statistics;
    const State direct = test::integrate(mesh, scene, direct_statistics);
    scene.solver.linear.type = LinearSolverType::petsc;
    const State petsc = test::integrate(mesh, scene, petsc_statistics);
    double difference = 0, scale = 0;
    for (std::size_t i = 0; i < direct.displacement.size(); ++i) {
      difference = std::max(difference, std::abs(petsc.displacement[i] - direct.displacement[i]));
      scale = std::max(scale, std::abs(direct.displacement[i]));
    }
    EXPECT_GT(scale, 0.0);
    EXPECT_LE(difference, 1e-8 * scale);
    EXPECT_GT(petsc_statistics.linear_iterations, direct_statistics.linear_iterations);  // it did iterate
  }
}

}  // namespace
}  // namespace tensormass
