// kernel_support.hpp's batch helpers: polar_rotation_batch gives every lane
// the rotation polar_rotation<D> gives it alone, whatever the other lanes
// hold (large rotations, strong compression, reflections, singular F).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "tensormass/kernels/kernel_support.hpp"

namespace tmtest {
namespace {

using tensormass::kernel::polar_rotation;
using tensormass::kernel::polar_rotation_batch;

/// H = Q S - I: Q the rotation by `angle` about a random axis, S = I + strain
/// times a random symmetric matrix with entries in [-1, 1].
std::array<double, 9> rotated_strain(double angle, double strain, std::mt19937_64& random) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double axis[3] = {unit(random), unit(random), unit(random)};
  const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& a : axis) a /= length;
  const double K[9] = {0, -axis[2], axis[1], axis[2], 0, -axis[0], -axis[1], axis[0], 0};
  double Q[9], S[9];
  for (int i = 0; i < 9; ++i) {
    double K2 = 0.0;
    for (int k = 0; k < 3; ++k) K2 += K[i / 3 * 3 + k] * K[k * 3 + i % 3];
    Q[i] = (i % 4 == 0 ? 1.0 : 0.0) + std::sin(angle) * K[i] + (1.0 - std::cos(angle)) * K2;  // Rodrigues
  }
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) S[i * 3 + j] = S[j * 3 + i] = (i == j ? 1.0 : 0.0) + strain * unit(random);
  std::array<double, 9> H{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double sum = 0.0;
      for (int k = 0; k < 3; ++k) sum += Q[i * 3 + k] * S[k * 3 + j];
      H[i * 3 + j] = sum - (i == j ? 1.0 : 0.0);
    }
  return H;
}

/// The lanes' H (each D*D) in structure of arrays, their rotations by
/// polar_rotation_batch, and back lane by lane.
template <int D, int W>
std::vector<std::array<double, D * D>> rotations_of_batch(const std::vector<std::array<double, D * D>>& lanes) {
  double H[D * D * W], R[D * D * W];
  for (int l = 0; l < W; ++l)
    for (int i = 0; i < D * D; ++i) H[i * W + l] = lanes[l][i];
  polar_rotation_batch<D, W>(H, R);
  std::vector<std::array<double, D * D>> rotations(W);
  for (int l = 0; l < W; ++l)
    for (int i = 0; i < D * D; ++i) rotations[l][i] = R[i * W + l];
  return rotations;
}

template <int D>
std::array<double, D * D> rotation_alone(const std::array<double, D * D>& H) {
  std::array<double, D * D> R{};
  polar_rotation<D>(H.data(), R.data());
  return R;
}

double largest_difference(const double* a, const double* b, int size) {
  double largest = 0.0;
  for (int i = 0; i < size; ++i) largest = std::max(largest, std::abs(a[i] - b[i]));
  return largest;
}

template <int W>
void expect_lanes_as_alone_3d(const std::vector<std::array<double, 9>>& lanes, double tolerance) {
  const auto batched = rotations_of_batch<3, W>(lanes);
  for (int l = 0; l < W; ++l) {
    const auto alone = rotation_alone<3>(lanes[l]);
    EXPECT_LE(largest_difference(batched[l].data(), alone.data(), 9), tolerance) << "lane " << l << " of " << W;
  }
}

TEST(PolarRotationBatch, EveryLaneGetsItsOwnRotationIn3D) {
  std::mt19937_64 random(7);
  // Mixed lanes: a large rotation with strain, strong compression, a near
  // identity, and a reflection (det F < 0) that converges to an orthogonal
  // factor of determinant -1.
  std::vector<std::array<double, 9>> lanes = {rotated_strain(2.5, 0.2, random), rotated_strain(0.3, 0.6, random),
                                              rotated_strain(0.01, 1e-4, random), rotated_strain(1.0, 0.1, random)};
  for (int i = 0; i < 3; ++i)
    lanes[3][i] = -(lanes[3][i] + (i == 0 ? 1.0 : 0.0)) - (i == 0 ? 1.0 : 0.0);  // row 0 of F flipped
  expect_lanes_as_alone_3d<4>(lanes, 1e-12);
  expect_lanes_as_alone_3d<2>(lanes, 1e-12);
  const auto batched = rotations_of_batch<3, 4>(lanes);
  for (int l = 0; l < 4; ++l) {  // orthogonal: R^T R = I
    const auto& R = batched[l];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double sum = 0.0;
        for (int k = 0; k < 3; ++k) sum += R[k * 3 + i] * R[k * 3 + j];
        EXPECT_NEAR(sum, i == j ? 1.0 : 0.0, 1e-13) << "lane " << l;
      }
  }
}

TEST(PolarRotationBatch, ManyRandomBatchesAgreeWithTheLaneAlone) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> angle(-3.0, 3.0), strain(0.0, 0.4);
  for (int batch = 0; batch < 200; ++batch) {
    std::vector<std::array<double, 9>> lanes;
    for (int l = 0; l < 4; ++l) lanes.push_back(rotated_strain(angle(random), strain(random), random));
    expect_lanes_as_alone_3d<4>(lanes, 1e-12);
  }
}

/// A singular F in one lane (F = 0: no rotation exists) sends the batch to
/// polar_rotation<3> lane by lane: every lane, the singular one included,
/// gets exactly what it gets alone.
TEST(PolarRotationBatch, ASingularLaneLeavesEveryLaneAsAlone) {
  std::mt19937_64 random(3);
  std::vector<std::array<double, 9>> lanes = {rotated_strain(0.7, 0.1, random), std::array<double, 9>{},
                                              rotated_strain(1.5, 0.3, random), rotated_strain(0.2, 0.05, random)};
  lanes[1] = {-1, 0, 0, 0, -1, 0, 0, 0, -1};
  expect_lanes_as_alone_3d<4>(lanes, 0.0);
  lanes[1][0] = std::nan("");  // not finite: the same
  expect_lanes_as_alone_3d<4>(lanes, 0.0);
}

TEST(PolarRotationBatch, EveryLaneGetsItsOwnRotationIn2D) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<double, 4>> lanes(4);
  for (auto& H : lanes)
    for (double& h : H) h = 0.8 * unit(random);
  lanes[2] = {-2.0, 0.0, 0.0, -2.0};  // F = -I, a rotation by pi: tan(theta) = 0 / 0, taken as the identity
  const auto batched = rotations_of_batch<2, 4>(lanes);
  for (int l = 0; l < 4; ++l) {
    const auto alone = rotation_alone<2>(lanes[l]);
    EXPECT_LE(largest_difference(batched[l].data(), alone.data(), 4), 1e-15) << "lane " << l;
  }
}

}  // namespace
}  // namespace tmtest
