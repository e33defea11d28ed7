// Projection of a symmetric matrix onto the positive semi-definite cone
// (psd_projection.cpp): clamped eigenvalues, kept eigenvectors, untouched
// when already positive semi-definite.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "tensormass/assembly/psd_projection.hpp"

namespace tensormass {
namespace {

/// Q diag(values) Q^T with Q the rotation by `angle` in the (0, 1) plane
/// and the identity elsewhere (3 x 3, row-major).
std::array<double, 9> rotated_diagonal(std::array<double, 3> values, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  const double Q[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
  std::array<double, 9> A{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) A[i * 3 + j] += Q[i][k] * values[k] * Q[j][k];
  return A;
}

TEST(PsdProjection, ClampsNegativeEigenvaluesAndKeepsTheEigenvectors) {
  std::array<double, 9> A = rotated_diagonal({-2.0, 3.0, 0.5}, 0.4);
  EXPECT_TRUE(project_to_positive_semidefinite(A.data(), 3));
  const std::array<double, 9> expected = rotated_diagonal({0.0, 3.0, 0.5}, 0.4);
  for (int e = 0; e < 9; ++e) EXPECT_NEAR(A[e], expected[e], 1e-14);
}

TEST(PsdProjection, LeavesAPositiveSemidefiniteMatrixBitwiseUnchanged) {
  std::array<double, 9> A = rotated_diagonal({0.0, 3.0, 0.5}, 1.1);
  A[2] = A[6] = 0.0;  // exact zeros stay exact
  const std::array<double, 9> before = A;
  // Round-off may put the zero eigenvalue at -1e-17: clamping it is a change
  // of that size, so only matrices with a clear margin are asserted unchanged.
  std::array<double, 9> B = rotated_diagonal({1.0, 3.0, 0.5}, 1.1);
  const std::array<double, 9> b_before = B;
  EXPECT_FALSE(project_to_positive_semidefinite(B.data(), 3));
  EXPECT_EQ(B, b_before);
  project_to_positive_semidefinite(A.data(), 3);
  for (int e = 0; e < 9; ++e) EXPECT_NEAR(A[e], before[e], 1e-14);
}

TEST(PsdProjection, NegativeDefiniteBecomesZero) {
  std::array<double, 4> A = {-1.0, 0.2, 0.2, -3.0};
  EXPECT_TRUE(project_to_positive_semidefinite(A.data(), 2));
  for (double a : A) EXPECT_NEAR(a, 0.0, 1e-15);
}

}  // namespace
}  // namespace tensormass
