// The fbar kernels (the mean-dilatation formulation, mean_dilatation.hpp)
// against references of their own: the whole kernel under a homogeneous
// deformation (J̄ = J, so F̄ = F), the B-bar stiffness written out here for
// Hooke at rest, and the volumetric stiffness of one element, of rank one
// (one dilatation per element) where the whole kernel's has one per point.
// Their derivatives are checked with every kernel's in test_derivatives.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "kernel_test_support.hpp"

namespace {

using namespace tmtest;

const tm_kernel& whole_of(const tm_kernel& kernel) { return registry().get(kernel.law, kernel.element, "whole"); }

/// The same rest shape and material as `other`, under `kernel`.
Element same_element(const tm_kernel& kernel, const Element& other) {
  Element e = other;
  e.kernel = &kernel;
  e.consts.assign(static_cast<std::size_t>(kernel.consts), 0.0);
  e.status = kernel.precompute(e.rest.data(), e.params.data(), kernel.params, e.consts.data());
  return e;
}

/// young and poisson of the Lamé constants.
Vector elastic_parameters(double lam, double mu) {
  return {mu * (3 * lam + 2 * mu) / (lam + mu), lam / (2 * (lam + mu))};
}

Element with_parameters(const tm_kernel& kernel, const Element& other, const Vector& params) {
  Element e = other;
  e.params = params;
  return same_element(kernel, e);
}

class FbarKernel : public testing::TestWithParam<const tm_kernel*> {};

/// An affine element under a homogeneous F has one J at every point, so
/// F̄ = F: the energy, force and stress are the whole kernel's.
TEST_P(FbarKernel, HomogeneousDeformationIsTheWholeKernels) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 61, /*affine=*/true);
  ASSERT_EQ(e.status, 0);
  const Element reference = same_element(whole_of(kernel), e);
  ASSERT_EQ(reference.status, 0);
  const Matrix3 F = {1.04, 0.02, -0.01, 0.03, 0.97, 0.02, -0.02, 0.01, 1.05};  // det != 1
  const Vector u = homogeneous_displacement(e, F);
  EXPECT_LE(relative_error(energy(e, u), energy(reference, u)), 1e-12);
  EXPECT_LE(relative_error(gradient(e, u), gradient(reference, u)), 1e-11);
  EXPECT_LE(relative_error(stress(e, u), stress(reference, u)), 1e-11);
}

/// Away from homogeneous states the two energies differ (the test above is
/// not comparing a kernel with itself).
TEST_P(FbarKernel, DiffersFromTheWholeKernelUnderNonUniformDilatation) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 62);
  const Element reference = same_element(whole_of(kernel), e);
  const Vector u = random_displacement(e, 63, 0.05, 0.03);
  EXPECT_GT(relative_error(gradient(e, u), gradient(reference, u)), 1e-6);
}

INSTANTIATE_TEST_SUITE_P(Registry, FbarKernel, testing::ValuesIn(kernels_where([](const tm_kernel& k) {
                           return std::string(k.split) == "fbar";
                         })),
                         KernelParamName());
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(FbarKernel);

class HookeFbar : public testing::TestWithParam<const tm_kernel*> {};

/// The B-bar energy of Hooke, written out from the kernel's point data
/// (consts: lam, mu, then per point w and G^T): at each point the small
/// strain with its trace replaced by the element's mean,
/// ε̄ = ε + (θ̄ - θ)/d I, θ̄ = Σ w θ / Σ w, and W = Σ w (λ/2 tr(ε̄)² + μ ε̄:ε̄).
/// `averaged` false gives the plain Hooke energy (the formula's own check).
double bbar_energy(const Element& e, const Vector& u, bool averaged) {
  const tm_kernel& k = *e.kernel;
  const int d = k.dim, n = k.nodes, stride = 1 + d * n;
  const auto [lam, mu] = lame(e.params);
  std::vector<Vector> strain(static_cast<std::size_t>(k.quadrature_points), Vector(9, 0.0));
  double volume = 0.0, dilatation = 0.0;
  for (int q = 0; q < k.quadrature_points; ++q) {
    const double* point = e.consts.data() + k.derived_params + q * stride;
    double H[9] = {};
    for (int a = 0; a < d; ++a)
      for (int c = 0; c < d; ++c)
        for (int j = 0; j < n; ++j) H[a * 3 + c] += u[static_cast<std::size_t>(j * d + a)] * point[1 + c * n + j];
    Vector& eps = strain[static_cast<std::size_t>(q)];
    for (int a = 0; a < d; ++a)
      for (int c = 0; c < d; ++c) eps[static_cast<std::size_t>(a * 3 + c)] = 0.5 * (H[a * 3 + c] + H[c * 3 + a]);
    volume += point[0];
    for (int a = 0; a < d; ++a) dilatation += point[0] * eps[static_cast<std::size_t>(a * 4)];
  }
  const double mean = dilatation / volume;
  double W = 0.0;
  for (int q = 0; q < k.quadrature_points; ++q) {
    const double w = e.consts[static_cast<std::size_t>(k.derived_params + q * stride)];
    Vector eps = strain[static_cast<std::size_t>(q)];
    double trace = 0.0;
    for (int a = 0; a < d; ++a) trace += eps[static_cast<std::size_t>(a * 4)];
    if (averaged)
      for (int a = 0; a < d; ++a) eps[static_cast<std::size_t>(a * 4)] += (mean - trace) / d;
    double tr = 0.0, squares = 0.0;
    for (int a = 0; a < d; ++a) tr += eps[static_cast<std::size_t>(a * 4)];
    for (double x : eps) squares += x * x;
    W += w * (0.5 * lam * tr * tr + mu * squares);
  }
  return W;
}

/// The Hessian of a quadratic energy by polarisation: K_ij = W(e_i + e_j) - W(e_i) - W(e_j).
Vector quadratic_hessian(const Element& e, bool averaged) {
  const auto dofs = static_cast<std::size_t>(e.kernel->dofs);
  Vector K(dofs * dofs), unit(dofs, 0.0), single(dofs);
  for (std::size_t i = 0; i < dofs; ++i) {
    unit.assign(dofs, 0.0);
    unit[i] = 1.0;
    single[i] = bbar_energy(e, unit, averaged);
  }
  for (std::size_t i = 0; i < dofs; ++i)
    for (std::size_t j = 0; j < dofs; ++j) {
      unit.assign(dofs, 0.0);
      unit[i] += 1.0;
      unit[j] += 1.0;
      K[i * dofs + j] = i == j ? 2.0 * single[i] : bbar_energy(e, unit, averaged) - single[i] - single[j];
    }
  return K;
}

/// At rest the fbar Hooke kernel's stiffness is the B-bar stiffness.
TEST_P(HookeFbar, RestStiffnessIsBbar) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 71);
  ASSERT_EQ(e.status, 0);
  const Vector zero(e.rest.size(), 0.0);
  const Element plain = same_element(whole_of(kernel), e);
  ASSERT_LE(relative_error(quadratic_hessian(e, false), hessian(plain, zero)), 1e-10) << "the reference formula";
  EXPECT_LE(relative_error(hessian(e, zero), quadratic_hessian(e, true)), 1e-10);
}

/// Numerical rank of a symmetric matrix: pivots of a fully pivoted
/// elimination above `tolerance` times the largest entry.
int rank(Vector A, std::size_t n, double tolerance) {
  double largest = max_abs(A);
  int result = 0;
  std::vector<bool> used(n, false);
  for (std::size_t step = 0; step < n; ++step) {
    std::size_t row = n, col = n;
    double pivot = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < n && !used[i]; ++j)
        if (std::abs(A[i * n + j]) > std::abs(pivot)) pivot = A[i * n + j], row = i, col = j;
    if (row == n || std::abs(pivot) <= tolerance * largest) break;
    used[row] = true;
    ++result;
    for (std::size_t i = 0; i < n; ++i) {
      if (i == row) continue;
      const double factor = A[i * n + col] / pivot;
      for (std::size_t j = 0; j < n; ++j) A[i * n + j] -= factor * A[row * n + j];
    }
    for (std::size_t j = 0; j < n; ++j) A[row * n + j] = 0.0;
  }
  return result;
}

/// dK/dλ at rest, μ fixed: the volumetric stiffness. Its rank is the number
/// of volume constraints the element imposes as λ grows: one for fbar (no
/// volumetric locking), more for the whole kernel (one per point, up to the
/// dofs a rigid motion leaves).
int volumetric_rank(const tm_kernel& kernel, const Element& shape) {
  const double mu = 1e4, lam_low = 1e5, lam_high = 2e5;
  const Vector zero(shape.rest.size(), 0.0);
  const Vector K_low = hessian(with_parameters(kernel, shape, elastic_parameters(lam_low, mu)), zero);
  const Vector K_high = hessian(with_parameters(kernel, shape, elastic_parameters(lam_high, mu)), zero);
  Vector volumetric(K_low.size());
  for (std::size_t i = 0; i < K_low.size(); ++i) volumetric[i] = (K_high[i] - K_low[i]) / (lam_high - lam_low);
  return rank(volumetric, static_cast<std::size_t>(kernel.dofs), 1e-9);
}

TEST_P(HookeFbar, OneVolumeConstraintPerElement) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 72);
  ASSERT_EQ(e.status, 0);
  EXPECT_EQ(volumetric_rank(kernel, e), 1);
  EXPECT_GT(volumetric_rank(whole_of(kernel), e), 1);
}

INSTANTIATE_TEST_SUITE_P(Registry, HookeFbar, testing::ValuesIn(kernels_where([](const tm_kernel& k) {
                           return std::string(k.split) == "fbar" && std::string(k.law) == "hooke";
                         })),
                         KernelParamName());
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(HookeFbar);

}  // namespace
