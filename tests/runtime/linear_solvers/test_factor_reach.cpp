// FactorReach: substitutions with CHOLMOD's supernodal factor, whole or
// over the supernodes a set of rows reaches, against CHOLMOD's own solve.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "grid_matrix.hpp"
#include "linear_solvers/factor_reach.hpp"
#include "tensormass/common/errors.hpp"

namespace {

using tensormass::detail::FactorReach;
using namespace tensormass::testing;

constexpr int kSide = 14;

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double largest = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

/// A^-1 b by the whole forward and back substitutions.
std::vector<double> whole_solve(const FactorReach& reach, const std::vector<double>& b) {
  std::vector<double> v(b.size()), x(b.size());
  reach.permute(b, v);
  reach.forward(v, false);
  reach.backward(v, false);
  reach.unpermute(v, x);
  return x;
}

TEST(FactorReach, WholeSubstitutionsSolveAsCholmodDoes) {
  const auto A = grid_laplacian(kSide, 0.1);
  CholmodFactor factor(A);
  const FactorReach reach(factor.factor());
  const std::vector<double> b = uneven_vector(A.rows);
  const std::vector<double> expected = factor.solve(b);
  const std::vector<double> zero(b.size(), 0.0);
  EXPECT_LT(largest_difference(whole_solve(reach, b), expected), 1e-12 * largest_difference(expected, zero));
}

TEST(FactorReach, ARightHandSideOnFewRowsIsSolvedThereOverTheirReachOnly) {
  const auto A = grid_laplacian(kSide, 0.1);
  CholmodFactor factor(A);
  FactorReach reach(factor.factor());
  const std::vector<int> rows = corner_rows(kSide, 4);
  const double share = reach.select(rows);
  EXPECT_GT(share, 0.0);
  EXPECT_LT(share, 0.8);  // a corner reaches its own subtree and the separators above it

  std::vector<double> b(A.rows, 0.0);
  for (int row : rows) b[row] = std::cos(0.3 * row) + 1.0;
  const std::vector<double> expected = factor.solve(b);
  std::vector<double> v(A.rows, 1e300);  // what lies off the selection must not be read
  reach.clear_selected(v);
  for (int row : rows) v[reach.position(row)] = b[row];
  reach.forward(v, true);
  reach.backward(v, true);
  double scale = 0.0;
  for (int row : rows) scale = std::max(scale, std::abs(expected[row]));
  for (int row : rows) EXPECT_NEAR(v[reach.position(row)], expected[row], 1e-12 * scale) << "row " << row;
}

TEST(FactorReach, EveryRowReachesTheWholeFactor) {
  const auto A = grid_laplacian(kSide, 0.1);
  CholmodFactor factor(A);
  FactorReach reach(factor.factor());
  std::vector<int> rows(A.rows);
  for (int i = 0; i < A.rows; ++i) rows[i] = i;
  EXPECT_DOUBLE_EQ(reach.select(rows), 1.0);
  EXPECT_DOUBLE_EQ(reach.select({}), 0.0);
}

TEST(FactorReach, ASimplicialFactorIsRefused) {
  const CholmodFactor simplicial(grid_laplacian(4, 0.1), CHOLMOD_SIMPLICIAL);
  EXPECT_THROW(FactorReach{simplicial.factor()}, tensormass::NumericalError);
}

}  // namespace
