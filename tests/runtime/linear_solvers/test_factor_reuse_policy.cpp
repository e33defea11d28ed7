// FactorReusePolicy: a new factor is asked for once a lagged solve costs
// more than the mean cost per solve since the last factorisation.
#include <gtest/gtest.h>

#include "linear_solvers/factor_reuse_policy.hpp"

namespace {

using tensormass::detail::FactorReusePolicy;

TEST(FactorReusePolicy, CheapLaggedSolvesKeepTheFactor) {
  FactorReusePolicy policy(30.0);
  policy.factorized();
  for (int solve = 0; solve < 50; ++solve) {
    policy.lagged_solve(2);
    EXPECT_FALSE(policy.refactorize()) << "solve " << solve;
  }
}

TEST(FactorReusePolicy, RefactorisesWhenASolveCostsMoreThanTheMean) {
  FactorReusePolicy policy(30.0);
  policy.factorized();     // cycle: 31 over 1 solve
  policy.lagged_solve(3);  // 34 / 2 = 17
  policy.lagged_solve(3);  // 37 / 3 = 12.3
  policy.lagged_solve(3);  // 40 / 4 = 10
  EXPECT_FALSE(policy.refactorize());
  policy.lagged_solve(12);  // 52 / 5 = 10.4 < 12: the mean starts rising
  EXPECT_TRUE(policy.refactorize());
  policy.factorized();
  EXPECT_FALSE(policy.refactorize());
}

TEST(FactorReusePolicy, ADearerFactorisationIsKeptLonger) {
  FactorReusePolicy cheap(5.0), dear(100.0);
  cheap.factorized();
  dear.factorized();
  cheap.lagged_solve(5);  // 11 / 2 = 5.5
  dear.lagged_solve(5);
  cheap.lagged_solve(6);  // 17 / 3 = 5.67 < 6
  dear.lagged_solve(6);
  EXPECT_TRUE(cheap.refactorize());
  EXPECT_FALSE(dear.refactorize());
}

}  // namespace
