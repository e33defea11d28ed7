// The polar rotation against the iteration it replaced (see polar_bench.hpp).
#include "polar_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "tensormass/kernels/kernel_support.hpp"
#include "tensormass/kernels/polar_decomposition.hpp"

namespace tensormass::bench {
namespace {

using Clock = std::chrono::steady_clock;

/// The baseline: Higham's scaled Newton iteration with the scale at every
/// step, stopping once a step moves X by less than 1e-10 (sessions 7 to 13).
void polar_rotation_scaled_every_step(const double* H, double* R) {
  for (int i = 0; i < 9; ++i) R[i] = H[i] + (i % 4 == 0 ? 1.0 : 0.0);
  for (int iteration = 0; iteration < 40; ++iteration) {
    const double c[9] = {R[4] * R[8] - R[5] * R[7], R[5] * R[6] - R[3] * R[8], R[3] * R[7] - R[4] * R[6],
                         R[2] * R[7] - R[1] * R[8], R[0] * R[8] - R[2] * R[6], R[1] * R[6] - R[0] * R[7],
                         R[1] * R[5] - R[2] * R[4], R[2] * R[3] - R[0] * R[5], R[0] * R[4] - R[1] * R[3]};
    const double det = R[0] * c[0] + R[1] * c[1] + R[2] * c[2];
    if (!(std::abs(det) > 0.0) || !std::isfinite(det)) return;
    const double z = 1.0 / std::cbrt(std::abs(det));
    const double inverse_scale = 1.0 / (det * z);
    double change = 0.0;
    for (int i = 0; i < 9; ++i) {
      const double next = 0.5 * (z * R[i] + inverse_scale * c[i]);
      change += std::abs(next - R[i]);
      R[i] = next;
    }
    if (change < 1e-10) return;
  }
}

/// H = Q S - I (9 per matrix): Q a rotation of random axis and angle (normal,
/// sigma 0.5 rad), S symmetric with entries I + strain * normal noise.
std::vector<double> random_gradients(int count, double strain, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> H(9 * static_cast<std::size_t>(count));
  for (int m = 0; m < count; ++m) {
    double axis[3] = {normal(rng), normal(rng), normal(rng)};
    const double length = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    for (double& a : axis) a /= length;
    const double angle = 0.5 * normal(rng);
    const double K[9] = {0, -axis[2], axis[1], axis[2], 0, -axis[0], -axis[1], axis[0], 0};
    double Q[9], S[9];
    for (int i = 0; i < 9; ++i) {
      double K2 = 0.0;
      for (int k = 0; k < 3; ++k) K2 += K[i / 3 * 3 + k] * K[k * 3 + i % 3];
      Q[i] = (i % 4 == 0 ? 1.0 : 0.0) + std::sin(angle) * K[i] + (1.0 - std::cos(angle)) * K2;  // Rodrigues
      S[i] = (i % 4 == 0 ? 1.0 : 0.0) + strain * normal(rng);
    }
    for (int i = 0; i < 3; ++i)
      for (int j = i + 1; j < 3; ++j) S[i * 3 + j] = S[j * 3 + i] = 0.5 * (S[i * 3 + j] + S[j * 3 + i]);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        double F = 0.0;
        for (int k = 0; k < 3; ++k) F += Q[i * 3 + k] * S[k * 3 + j];
        H[9 * m + i * 3 + j] = F - (i == j ? 1.0 : 0.0);
      }
  }
  return H;
}

template <class Polar>
double median_ns(Polar polar, const std::vector<double>& H, std::vector<double>& R, int repetitions) {
  const int count = static_cast<int>(H.size() / 9);
  std::vector<double> samples;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = Clock::now();
    for (int m = 0; m < count; ++m) polar(&H[9 * m], &R[9 * m]);
    samples.push_back(1e9 * std::chrono::duration<double>(Clock::now() - start).count() / count);
  }
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

/// H (9 per matrix) regrouped as batches of W lanes in structure of arrays (kernel_abi.h).
template <int W>
std::vector<double> in_batches(const std::vector<double>& H) {
  const std::size_t batches = H.size() / (9 * W);
  std::vector<double> packed(batches * 9 * W);
  for (std::size_t b = 0; b < batches; ++b)
    for (int l = 0; l < W; ++l)
      for (int i = 0; i < 9; ++i) packed[(b * 9 + i) * W + l] = H[(b * W + l) * 9 + i];
  return packed;
}

/// polar_rotation_batch over packed batches: ns per matrix (median), and
/// the rotations unpacked back to 9 per matrix.
template <int W>
double median_batch_ns(const std::vector<double>& H, std::vector<double>& R, int repetitions) {
  const std::vector<double> packed = in_batches<W>(H);
  std::vector<double> rotations(packed.size());
  const int batches = static_cast<int>(packed.size() / (9 * W));
  std::vector<double> samples;
  for (int r = 0; r < repetitions; ++r) {
    const auto start = Clock::now();
    for (int b = 0; b < batches; ++b) kernel::polar_rotation_batch<3, W>(&packed[9 * W * b], &rotations[9 * W * b]);
    samples.push_back(1e9 * std::chrono::duration<double>(Clock::now() - start).count() / (batches * W));
  }
  for (int b = 0; b < batches; ++b)
    for (int l = 0; l < W; ++l)
      for (int i = 0; i < 9; ++i) R[(b * W + l) * 9 + i] = rotations[(b * 9 + i) * W + l];
  std::sort(samples.begin(), samples.end());
  return samples[samples.size() / 2];
}

}  // namespace

std::vector<PolarTiming> print_polar_rotation_timings(int matrices, int repetitions, bool& agree) {
  std::printf("\n## 3D polar rotation (corotational kernels), ns per call, median of %d over %d matrices\n\n",
              repetitions, matrices);
  std::printf(
      "| strain | now | scaled every step, stop 1e-10 (before) | now / before | largest difference "
      "| batched, %d lanes (Newton-Schulz) | batched / now | its largest difference |\n",
      kernel::kBatchWidth);
  std::printf("|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::mt19937_64 rng(20261126);
  agree = true;
  std::vector<PolarTiming> timings;
  for (double strain : {0.001, 0.01, 0.1, 0.3}) {
    const std::vector<double> H = random_gradients(matrices, strain, rng);
    std::vector<double> now(H.size()), before(H.size()), batched(H.size());
    // Alternate them so that a drift of the machine touches all alike.
    double now_ns = 0.0, before_ns = 0.0, batched_ns = 0.0;
    for (int round = 0; round < 2; ++round) {
      before_ns += median_ns(polar_rotation_scaled_every_step, H, before, repetitions);
      now_ns += median_ns(kernel::polar_rotation<3>, H, now, repetitions);
      batched_ns += median_batch_ns<kernel::kBatchWidth>(H, batched, repetitions);
    }
    double difference = 0.0, batched_difference = 0.0;
    for (std::size_t i = 0; i < H.size(); ++i) {
      difference = std::max(difference, std::abs(now[i] - before[i]));
      batched_difference = std::max(batched_difference, std::abs(batched[i] - now[i]));
    }
    agree = agree && difference <= 1e-12 && batched_difference <= 1e-12;
    std::printf("| %g | %.1f | %.1f | %.2f | %.1e | %.1f | %.2f | %.1e |\n", strain, now_ns / 2, before_ns / 2,
                now_ns / before_ns, difference, batched_ns / 2, batched_ns / now_ns, batched_difference);
    timings.push_back({strain, now_ns / 2, before_ns / 2, batched_ns / 2, difference, batched_difference});
  }
  return timings;
}

}  // namespace tensormass::bench
