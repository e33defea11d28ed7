// Derivatives of every kernel of the registry: the gradient is the
// derivative of the energy, the Hessian the derivative of the gradient
// (central finite differences, step 1e-5 of the element size, with Richardson
// extrapolation: errors ~1e-10 against the required 1e-6), the Hessian is
// symmetric, gradient_hessian equals gradient and hessian, and the splits of
// one (law, element) pair agree.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

#include "kernel_test_support.hpp"

namespace tmtest {
namespace {

constexpr std::uint64_t kSeeds[] = {11, 12, 13};
/// Displacement gradients of up to 5 % and 20 % (plus nodal noise of a
/// fifth of that times the element size).
constexpr double kStrains[] = {0.05, 0.2};

class KernelDerivatives : public testing::TestWithParam<const tm_kernel*> {};

/// Three random elements (shape, material, displacement) per seed.
TEST_P(KernelDerivatives, GradientIsCentralDifferenceOfEnergy) {
  const tm_kernel& kernel = *GetParam();
  for (const std::uint64_t seed : kSeeds) {
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0) << "precompute rejected the rest shape of seed " << seed;
    for (const double strain : kStrains) {
      const Vector u = random_displacement(e, seed + 100, strain, strain / 5);
      const Vector g = gradient(e, u);
      const double h = 1e-5 * e.size;
      const Vector fd = richardson(fd_gradient(e, u, h), fd_gradient(e, u, h / 2));
      EXPECT_LE(relative_error(g, fd), 1e-6) << "seed " << seed << ", strain " << strain;
    }
  }
}

TEST_P(KernelDerivatives, HessianIsCentralDifferenceOfGradient) {
  const tm_kernel& kernel = *GetParam();
  for (const std::uint64_t seed : kSeeds) {
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0) << "precompute rejected the rest shape of seed " << seed;
    for (const double strain : kStrains) {
      const Vector u = random_displacement(e, seed + 200, strain, strain / 5);
      const Vector K = hessian(e, u);
      const double h = 1e-5 * e.size;
      const Vector fd = richardson(fd_hessian(e, u, h), fd_hessian(e, u, h / 2));
      EXPECT_LE(relative_error(K, fd), 1e-6) << "seed " << seed << ", strain " << strain;
    }
  }
}

TEST_P(KernelDerivatives, HessianIsSymmetric) {
  const tm_kernel& kernel = *GetParam();
  const auto dofs = static_cast<std::size_t>(kernel.dofs);
  for (const std::uint64_t seed : kSeeds) {
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    const Vector K = hessian(e, random_displacement(e, seed + 300));
    Vector transposed(K.size());
    for (std::size_t i = 0; i < dofs; ++i)
      for (std::size_t j = 0; j < dofs; ++j) transposed[j * dofs + i] = K[i * dofs + j];
    EXPECT_LE(relative_error(K, transposed), 1e-12) << "seed " << seed;
    EXPECT_GT(max_abs(K), 0.0);
  }
}

TEST_P(KernelDerivatives, GradientHessianMatchesSeparateCalls) {
  const tm_kernel& kernel = *GetParam();
  for (const std::uint64_t seed : kSeeds) {
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    const Vector u = random_displacement(e, seed + 400);
    Vector g(static_cast<std::size_t>(kernel.dofs), -1.0), K(g.size() * g.size(), -1.0);
    kernel.gradient_hessian(u.data(), e.consts.data(), g.data(), K.data());
    EXPECT_LE(relative_error(g, gradient(e, u)), 1e-12) << "seed " << seed;
    EXPECT_LE(relative_error(K, hessian(e, u)), 1e-12) << "seed " << seed;
  }
}

/// The energy is a potential: W(u) - W(0) equals the line integral of the
/// gradient along the straight path (Simpson's rule on a fine grid), a
/// check independent of the step size of the differences above.
TEST_P(KernelDerivatives, EnergyIsLineIntegralOfGradient) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 21);
  ASSERT_EQ(e.status, 0);
  const Vector u = random_displacement(e, 22);
  const Vector zero(u.size(), 0.0);
  const int intervals = 64;
  double integral = 0.0;
  for (int k = 0; k <= intervals; ++k) {
    const double t = static_cast<double>(k) / intervals;
    Vector ut(u.size());
    for (std::size_t i = 0; i < u.size(); ++i) ut[i] = t * u[i];
    const Vector g = gradient(e, ut);
    double dot = 0.0;
    for (std::size_t i = 0; i < u.size(); ++i) dot += g[i] * u[i];
    const double weight = (k == 0 || k == intervals) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
    integral += weight * dot / (3.0 * intervals);
  }
  const double increase = energy(e, u) - energy(e, zero);
  EXPECT_GT(increase, 0.0);
  EXPECT_LE(relative_error(increase, integral), 1e-8);
}

INSTANTIATE_TEST_SUITE_P(AllKernels, KernelDerivatives, testing::ValuesIn(all_kernels()), KernelParamName());

// --- Splits of one (law, element) pair -------------------------------------

class SplitAgreement : public testing::TestWithParam<LawElement> {};

/// The largest difference over the larger of the values' size and `floor`.
double difference_over(const Vector& actual, const Vector& expected, double floor) {
  return max_abs_difference(actual, expected) / std::max({max_abs(actual), max_abs(expected), floor});
}

double difference_over(double actual, double expected, double floor) {
  return difference_over(Vector{actual}, Vector{expected}, floor);
}

TEST_P(SplitAgreement, SplitsAgreeWithWhole) {
  const LawElement& pair = GetParam();
  const tm_kernel* whole = registry().find(pair.law, pair.element, "whole");
  ASSERT_NE(whole, nullptr) << "no whole split";
  int compared = 0;
  for (const char* split : {"terms", "tensor"}) {
    const tm_kernel* other = registry().find(pair.law, pair.element, split);
    if (other == nullptr) continue;
    ++compared;
    for (const std::uint64_t seed : kSeeds) {
      SCOPED_TRACE(std::string(split) + " vs whole, seed " + std::to_string(seed));
      // Same seed: same rest shape, material and displacement for both splits.
      const Element a = make_element(*whole, seed), b = make_element(*other, seed);
      ASSERT_EQ(a.status, 0);
      ASSERT_EQ(b.status, 0);
      ASSERT_EQ(a.rest, b.rest);
      for (const double strain : {0.0, 0.02, 0.1}) {
        SCOPED_TRACE("strain " + std::to_string(strain));
        const Vector u =
            strain == 0.0 ? Vector(a.rest.size(), 0.0) : random_displacement(a, seed + 500, strain, strain / 5);
        // At rest a law whose stress cancels in floating point (stable
        // neo-Hookean: mu' 3/4 - lam' mu/lam') leaves round-off of either
        // sign: compare against the forces of a unit strain there.
        const double force_scale = max_abs(hessian(a, u)) * a.size;
        const double modulus = stress_scale(hessian(a, Vector(a.rest.size(), 0.0)), a.size, a.kernel->dim);
        EXPECT_LE(difference_over(energy(b, u), energy(a, u), force_scale * a.size), 1e-12) << "energy";
        EXPECT_LE(difference_over(gradient(b, u), gradient(a, u), force_scale), 1e-12) << "gradient";
        EXPECT_LE(relative_error(hessian(b, u), hessian(a, u)), 1e-12) << "hessian";
        EXPECT_LE(difference_over(stress(b, u), stress(a, u), modulus), 1e-12) << "stress";
        Vector ga(a.rest.size()), Ka(ga.size() * ga.size()), gb(ga.size()), Kb(Ka.size());
        whole->gradient_hessian(u.data(), a.consts.data(), ga.data(), Ka.data());
        other->gradient_hessian(u.data(), b.consts.data(), gb.data(), Kb.data());
        EXPECT_LE(difference_over(gb, ga, force_scale), 1e-12) << "gradient_hessian: gradient";
        EXPECT_LE(relative_error(Kb, Ka), 1e-12) << "gradient_hessian: hessian";
      }
    }
  }
  EXPECT_GE(compared, 1) << "only the whole split exists";
}

/// The (law, element) pairs of the registry with a split besides whole.
std::vector<LawElement> pairs_with_several_splits() {
  std::vector<LawElement> result;
  for (const LawElement& pair : law_element_pairs())
    if (registry().find(pair.law, pair.element, "terms") || registry().find(pair.law, pair.element, "tensor"))
      result.push_back(pair);
  return result;
}

INSTANTIATE_TEST_SUITE_P(AllPairs, SplitAgreement, testing::ValuesIn(pairs_with_several_splits()),
                         LawElementParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(SplitAgreement);

}  // namespace
}  // namespace tmtest
