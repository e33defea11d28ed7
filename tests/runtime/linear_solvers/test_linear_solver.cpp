// What every linear solver shares (tensormass/linear_solvers/linear_solver.hpp):
// the factory choosing the solver of the settings, a checkpointed factor
// refused by a solver that keeps none, and the free nodes told to the solver
// only when every node is wholly free or wholly held. (Each solver's
// solves: test_cg_solver.cpp, test_cholmod_solver.cpp, test_petsc_solver.cpp;
// distribute() refused off PETSc: parallel/test_distribution.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "grid_matrix.hpp"
#include "support/cantilever.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// A solver that only records what set_node_blocks was told.
class RecordingSolver : public LinearSolver {
 public:
  void factorize(const SparseMatrix&) override {}
  int solve(std::span<const double>, std::span<double>, double) override { return 0; }
  std::string name() const override { return "recording"; }
  void set_node_blocks(int dim, std::span<const double> coordinates) override {
    ++calls;
    block_dim = dim;
    block_coordinates.assign(coordinates.begin(), coordinates.end());
  }
  int calls = 0;
  int block_dim = 0;
  std::vector<double> block_coordinates;
};

LinearSolverSettings settings_of(LinearSolverType type) {
  LinearSolverSettings settings;
  settings.type = type;
  return settings;
}

TEST(LinearSolver, TheFactoryMakesTheSolverOfTheSettings) {
  EXPECT_EQ(make_linear_solver(settings_of(LinearSolverType::cholmod))->name(), "cholmod");
  EXPECT_EQ(make_linear_solver(settings_of(LinearSolverType::cg))->name(), "cg (Jacobi)");
  if (petsc_available()) {
    const std::string name = make_linear_solver(settings_of(LinearSolverType::petsc))->name();
    EXPECT_NE(name.find("petsc"), std::string::npos) << name;
  } else {  // reached only by code that skips the scene, which refuses petsc itself
    try {
      make_linear_solver(settings_of(LinearSolverType::petsc));
      ADD_FAILURE() << "a PETSc solver from a build without PETSc";
    } catch (const std::invalid_argument& error) {
      EXPECT_STREQ(error.what(), "this build has no PETSc (configure with libpetsc-real-dev installed)");
    }
  }
}

TEST(LinearSolver, TheFactoriesSolversSolveTheSameSystem) {
  const SparseMatrix A = testing::grid_laplacian(6, 0.5);
  std::vector<double> b(static_cast<std::size_t>(A.rows));
  for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::sin(0.3 * static_cast<double>(i));
  std::vector<std::vector<double>> solutions;
  for (LinearSolverType type : {LinearSolverType::cholmod, LinearSolverType::cg}) {
    const auto solver = make_linear_solver(settings_of(type));
    solver->factorize(A);
    std::vector<double> x(b.size(), 0.0);
    EXPECT_GE(solver->solve(b, x, 1e-12), 1);
    solutions.push_back(x);
  }
  for (std::size_t i = 0; i < b.size(); ++i) EXPECT_NEAR(solutions[1][i], solutions[0][i], 1e-9) << i;
}

TEST(LinearSolver, ASolverKeepingNoFactorRefusesACheckpointedOne) {
  const SparseMatrix A = testing::grid_laplacian(3, 1.0);
  const auto cg = make_linear_solver(settings_of(LinearSolverType::cg));
  EXPECT_TRUE(cg->save_state().empty());
  EXPECT_NO_THROW(cg->restore_state({}, A));
  const std::vector<double> saved{1.0, 2.0};
  try {
    cg->restore_state(saved, A);
    ADD_FAILURE() << "a factor was accepted";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(),
                 "the checkpoint holds a direct solver's factor; this run's linear solver (cg (Jacobi)) keeps none");
  }
}

TEST(LinearSolver, TheFreeNodesAreToldWithTheirRestPositions) {
  const Mesh mesh = test::beam(2, "quad4", {3, 1, 1});  // nodes on x = 0, 1, 2, 3 (and y = 0, 1)
  const Model model(mesh, test::cantilever("hooke").model);
  RecordingSolver solver;
  describe_free_nodes(solver, model);
  ASSERT_EQ(solver.calls, 1);
  EXPECT_EQ(solver.block_dim, 2);
  std::vector<double> expected;
  for (int node = 0; node < model.mesh().node_count(); ++node)
    if (model.mesh().rest_positions[3 * node] > 1e-12)  // not clamped at x = 0
      expected.insert(expected.end(),
                      {model.mesh().rest_positions[3 * node], model.mesh().rest_positions[3 * node + 1]});
  EXPECT_EQ(solver.block_coordinates, expected);
  EXPECT_EQ(expected.size(), 12u);
}

TEST(LinearSolver, NothingIsToldWhenANodeIsHeldInSomeComponentsOnly) {
  const Mesh mesh = test::beam(2, "quad4", {3, 1, 1});
  Scene scene = test::cantilever("hooke");
  PrescribedSpec slide;
  slide.region = "tip";
  slide.components = {true, false, false};  // the tip held along x, free along y
  scene.model.prescribed.push_back(slide);
  const Model model(mesh, scene.model);
  RecordingSolver solver;
  describe_free_nodes(solver, model);
  EXPECT_EQ(solver.calls, 0);
}

}  // namespace
}  // namespace tensormass
