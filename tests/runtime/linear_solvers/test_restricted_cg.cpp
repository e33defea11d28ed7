// restricted_cg: CG preconditioned by an old factor, run on the rows where
// the matrix changed since, against CG on every row and a direct solve.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grid_matrix.hpp"
#include "linear_solvers/factor_reach.hpp"
#include "linear_solvers/preconditioned_cg.hpp"
#include "linear_solvers/restricted_cg.hpp"

namespace {

using namespace tensormass::detail;
using namespace tensormass::testing;
using tensormass::SparseMatrix;

constexpr int kSide = 14;

/// A grid matrix factorised, then stiffened in a corner block.
struct Problem {
  SparseMatrix old_matrix = grid_laplacian(kSide, 0.1);
  std::vector<int> block = corner_rows(kSide, 5);
  SparseMatrix matrix = stiffened(old_matrix, block, 30.0);
  std::vector<double> b = uneven_vector(old_matrix.rows);
  CholmodFactor factor{old_matrix};
  FactorReach reach{factor.factor()};
  ChangedBlock change = changed_block(matrix, old_matrix.values);
  RestrictedWorkspace workspace;
  std::vector<double> x = std::vector<double>(b.size(), 0.0);
  Problem() { reach.select(change.rows); }
};

TEST(RestrictedCg, TheChangedBlockHoldsTheRowsAndTheDifference) {
  const Problem p;
  EXPECT_EQ(p.change.rows, p.block);
  std::vector<double> ones(p.block.size(), 1.0), sums(p.block.size(), 0.0);
  p.change.multiply_add(ones, sums);  // D 1: the added Laplacian's rows sum to its diagonal shift
  for (double sum : sums) EXPECT_NEAR(sum, 60.0, 1e-12);
}

TEST(RestrictedCg, SolvesTheChangedMatrixToTheTolerance) {
  Problem p;
  EXPECT_LT(p.reach.select(p.change.rows), 0.9);
  for (double guess : {0.0, 0.3}) {
    std::vector<double> x(p.b.size(), guess);
    const PcgResult result = restricted_cg(p.reach, p.change, p.b, x, 1e-10, 100, p.workspace);
    EXPECT_TRUE(result.converged);
    EXPECT_GT(result.iterations, 1);
    EXPECT_LT(relative_residual(p.matrix, p.b, x), 1e-9) << "guess " << guess;
  }
}

TEST(RestrictedCg, TakesTheIterationsOfCgOnEveryRowFromTheSameStart) {
  Problem p;
  const PcgResult on_block = restricted_cg(p.reach, p.change, p.b, p.x, 1e-10, 100, p.workspace);

  std::vector<double> y = p.factor.solve(p.b);  // restricted_cg's start from a zero guess
  PcgWorkspace whole;
  const auto old_factor = [&](std::span<const double> r, std::span<double> z) {
    const std::vector<double> solved = p.factor.solve(std::vector<double>(r.begin(), r.end()));
    std::copy(solved.begin(), solved.end(), z.begin());
  };
  const PcgResult everywhere = preconditioned_cg(p.matrix, p.b, y, old_factor, 1e-10, 100, whole);
  EXPECT_NEAR(on_block.iterations, everywhere.iterations, 1);
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_NEAR(p.x[i], y[i], 1e-8 * std::abs(y[i]) + 1e-12) << i;
}

TEST(RestrictedCg, StopsAtTheIterationLimitWithTheLastIterate) {
  Problem p;
  const PcgResult result = restricted_cg(p.reach, p.change, p.b, p.x, 1e-14, 2, p.workspace);
  EXPECT_FALSE(result.converged);
  EXPECT_EQ(result.iterations, 2);
  EXPECT_NEAR(relative_residual(p.matrix, p.b, p.x), result.relative_residual, 1e-6 * result.relative_residual);
}

TEST(RestrictedCg, AnUnchangedMatrixIsSolvedByTheFactorAlone) {
  Problem p;
  const ChangedBlock unchanged = changed_block(p.old_matrix, p.old_matrix.values);
  EXPECT_TRUE(unchanged.rows.empty());
  p.reach.select(unchanged.rows);
  const PcgResult result = restricted_cg(p.reach, unchanged, p.b, p.x, 1e-10, 10, p.workspace);
  EXPECT_TRUE(result.converged);
  EXPECT_EQ(result.iterations, 0);
  EXPECT_LT(relative_residual(p.old_matrix, p.b, p.x), 1e-12);
}

}  // namespace
