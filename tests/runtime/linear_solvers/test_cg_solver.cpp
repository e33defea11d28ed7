// The conjugate-gradient solver (cg_solver.cpp) on a small SPD matrix: it
// reaches the requested tolerance, in fewer iterations for a looser one,
// and never factorises.
#include <gtest/gtest.h>

#include <vector>

#include "grid_matrix.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"

namespace {

using tensormass::LinearSolverSettings;
using tensormass::LinearSolverType;
using tensormass::SparseMatrix;
using tensormass::testing::laplacian;
using tensormass::testing::relative_residual;
using tensormass::testing::right_hand_side;

TEST(CgSolver, ReachesTheRequestedTolerance) {
  constexpr int n = 100;
  LinearSolverSettings settings;
  settings.type = LinearSolverType::cg;
  auto solver = tensormass::make_linear_solver(settings);
  const std::vector<double> b = right_hand_side(n);
  const SparseMatrix A = laplacian(n, 0.01);
  solver->factorize(A);
  int iterations[2];
  const double tolerances[2] = {1e-10, 1e-4};
  for (int k = 0; k < 2; ++k) {
    std::vector<double> x(n, 0.0);
    iterations[k] = solver->solve(b, x, tolerances[k]);
    EXPECT_LT(relative_residual(A, b, x), tolerances[k]);
  }
  EXPECT_LT(iterations[1], iterations[0]);
  EXPECT_EQ(solver->factorizations(), 0);
}

}  // namespace
