// region_last_ordering: a region's rows eliminated after all others, so
// that a right-hand side on the region reaches the region's supernodes only.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "grid_matrix.hpp"
#include "linear_solvers/factor_reach.hpp"
#include "linear_solvers/region_last_ordering.hpp"

namespace {

using tensormass::detail::dilated_rows;
using tensormass::detail::FactorReach;
using tensormass::detail::region_last_ordering;
using namespace tensormass::testing;

/// A started cholmod_common, finished with the test.
class Common {
 public:
  Common() { cholmod_start(&common_); }
  ~Common() { cholmod_finish(&common_); }
  Common(const Common&) = delete;
  Common& operator=(const Common&) = delete;
  cholmod_common& get() { return common_; }

 private:
  cholmod_common common_{};
};

TEST(RegionLastOrdering, EachRingAddsTheNeighboursOfTheLast) {
  const auto A = grid_laplacian(9, 0.1);
  const std::vector<int> centre = centre_rows(9, 1);
  EXPECT_EQ(dilated_rows(A, centre, 0), centre);
  EXPECT_EQ(dilated_rows(A, centre, 1).size(), 7u);   // the 7-point stencil
  EXPECT_EQ(dilated_rows(A, centre, 2).size(), 25u);  // 1 + 6 + 18 rows within two steps
  const std::vector<int> ring = dilated_rows(A, centre, 3);
  EXPECT_EQ(ring.size(), 63u);
  EXPECT_TRUE(std::is_sorted(ring.begin(), ring.end()));
  EXPECT_EQ(dilated_rows(A, {}, 2), std::vector<int>{});
}

TEST(RegionLastOrdering, ThePermutationEndsWithTheRegion) {
  const auto A = grid_laplacian(12, 0.1);
  const std::vector<int> region = dilated_rows(A, centre_rows(12, 2), 2);
  Common common;
  const std::vector<int> perm = region_last_ordering(A, region, common.get());
  ASSERT_EQ(perm.size(), static_cast<std::size_t>(A.rows));
  std::vector<int> sorted = perm;
  std::sort(sorted.begin(), sorted.end());
  for (int row = 0; row < A.rows; ++row) ASSERT_EQ(sorted[row], row);
  std::vector<int> tail(perm.end() - static_cast<std::ptrdiff_t>(region.size()), perm.end());
  std::sort(tail.begin(), tail.end());
  EXPECT_EQ(tail, region);
}

// CHOLMOD's nested dissection puts the grid's centre on its first
// separators, which hold much of the factor; the region ordered last
// reaches its own rows' columns only.
TEST(RegionLastOrdering, ARegionAtTheCentreReachesLessOfTheFactor) {
  constexpr int kSide = 16;
  const auto A = grid_laplacian(kSide, 0.1);
  const std::vector<int> changing = centre_rows(kSide, 2);
  CholmodFactor default_factor(A);
  FactorReach default_reach(default_factor.factor());
  const double default_share = default_reach.select(changing);

  Common common;
  const std::vector<int> region = dilated_rows(A, changing, 2);
  CholmodFactor region_factor(A, CHOLMOD_SUPERNODAL, region_last_ordering(A, region, common.get()));
  FactorReach region_reach(region_factor.factor());
  const double region_share = region_reach.select(changing);
  EXPECT_GT(default_share, 0.3) << "the centre should lie on the first separators";
  EXPECT_LT(region_share, 0.5 * default_share);
  // The solve is the same.
  const std::vector<double> b = uneven_vector(A.rows);
  const std::vector<double> x = default_factor.solve(b), y = region_factor.solve(b);
  for (int row = 0; row < A.rows; ++row) EXPECT_NEAR(x[row], y[row], 1e-10 * std::abs(x[row]) + 1e-12);
}

}  // namespace
