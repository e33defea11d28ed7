/// Tests of tensormass/kernels/tensor_split.hpp on hand-built elements (tri3, quad4
/// with four points, tet4) and an isotropic elasticity tensor: the
/// polynomial form's energy, gradient and Hessian against a direct
/// evaluation through the displacement gradient (Hooke: linear strain;
/// StVK: Green strain, P = F S) and against finite differences.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "tensormass/kernels/tensor_split.hpp"

namespace {

namespace tensor = tensormass::kernel::tensor;
using tensor::Strain;

constexpr double kLambda = 1.7;
constexpr double kMu = 0.9;

// --- Hand-built reference elements -------------------------------------------

/// Reference gradients dN/dr (points by nodes by dim) and weights of an element.
template <int D, int N, int Q>
struct Reference {
  double gradients[Q][N][D];
  double weights[Q];
};

Reference<2, 3, 1> tri3() { return {{{{-1.0, -1.0}, {1.0, 0.0}, {0.0, 1.0}}}, {0.5}}; }

Reference<3, 4, 1> tet4() {
  return {{{{-1.0, -1.0, -1.0}, {1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}}, {1.0 / 6.0}};
}

/// Bilinear quad on [-1, 1]^2 with 2 by 2 Gauss points.
Reference<2, 4, 4> quad4() {
  Reference<2, 4, 4> reference{};
  const double corners[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
  const double g = 1.0 / std::sqrt(3.0);
  const double points[4][2] = {{-g, -g}, {g, -g}, {g, g}, {-g, g}};
  for (int q = 0; q < 4; ++q) {
    reference.weights[q] = 1.0;
    for (int j = 0; j < 4; ++j) {
      const double rj = corners[j][0], sj = corners[j][1];
      reference.gradients[q][j][0] = 0.25 * rj * (1.0 + sj * points[q][1]);
      reference.gradients[q][j][1] = 0.25 * sj * (1.0 + rj * points[q][0]);
    }
  }
  return reference;
}

/// Reproducible values in [-1, 1] (a fixed linear congruential sequence).
std::vector<double> pseudo_random(int count, unsigned seed) {
  std::vector<double> values(count);
  unsigned state = seed;
  for (double& value : values) {
    state = state * 1664525u + 1013904223u;
    value = 2.0 * (state >> 8) / double(1u << 24) - 1.0;
  }
  return values;
}

/// Rest positions: the reference nodes (from the gradients' element) distorted.
template <int D, int N>
std::vector<double> rest_positions(const double (&nodes)[N][D], unsigned seed) {
  const std::vector<double> noise = pseudo_random(N * D, seed);
  std::vector<double> X(N * D);
  for (int j = 0; j < N; ++j)
    for (int a = 0; a < D; ++a) X[j * D + a] = 1.3 * nodes[j][a] + 0.1 * noise[j * D + a] + 0.05 * a;
  return X;
}

/// Isotropic CC_abce = lambda d_ab d_ce + mu (d_ac d_be + d_ae d_bc), row-major.
template <int D>
std::vector<double> isotropic_elasticity() {
  std::vector<double> CC(D * D * D * D);
  auto delta = [](int i, int j) { return i == j ? 1.0 : 0.0; };
  for (int a = 0; a < D; ++a)
    for (int b = 0; b < D; ++b)
      for (int c = 0; c < D; ++c)
        for (int e = 0; e < D; ++e)
          CC[((a * D + b) * D + c) * D + e] =
              kLambda * delta(a, b) * delta(c, e) + kMu * (delta(a, c) * delta(b, e) + delta(a, e) * delta(b, c));
  return CC;
}

// --- The element in tensor form and directly ---------------------------------

template <int D, int N, int Q, Strain S>
struct Element {
  static constexpr int dofs = D * N;
  static constexpr int stride = 1 + D * N;
  std::vector<double> consts;  // Q points (w, G^T), then the coefficients

  Element(const Reference<D, N, Q>& reference, const std::vector<double>& X)
      : consts(Q * stride + tensor::Layout<D, N, S>::total, -1.0) {
    const std::vector<double> CC = isotropic_elasticity<D>();
    const int status =
        tensor::precompute<D, N, Q, S>(X.data(), reference.gradients, reference.weights, CC.data(), consts.data());
    EXPECT_EQ(status, 0);
  }

  const double* coefficients() const { return consts.data() + Q * stride; }

  double energy(const std::vector<double>& u) const { return tensor::energy<D, N, S>(u.data(), coefficients()); }

  std::vector<double> gradient(const std::vector<double>& u) const {
    std::vector<double> g(dofs);
    tensor::gradient<D, N, S>(u.data(), coefficients(), g.data());
    return g;
  }

  std::vector<double> hessian(const std::vector<double>& u) const {
    std::vector<double> h(dofs * dofs);
    tensor::hessian<D, N, S>(u.data(), coefficients(), h.data());
    return h;
  }

  /// W and dW/du from the displacement gradient at each point: Hooke's law
  /// in eps = sym(H) (linear strain) or StVK in E = (F^T F - I)/2, P = F S.
  double direct(const std::vector<double>& u, std::vector<double>* gradient = nullptr) const {
    if (gradient) gradient->assign(dofs, 0.0);
    double W = 0.0;
    for (int q = 0; q < Q; ++q) {
      const double w = consts[q * stride];
      const double* GT = consts.data() + q * stride + 1;
      double H[D][D] = {}, F[D][D], strain[D][D], stress[D][D], P[D][D];
      for (int a = 0; a < D; ++a)
        for (int c = 0; c < D; ++c)
          for (int j = 0; j < N; ++j) H[a][c] += u[j * D + a] * GT[c * N + j];
      for (int a = 0; a < D; ++a)
        for (int c = 0; c < D; ++c) F[a][c] = (a == c ? 1.0 : 0.0) + H[a][c];
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          if constexpr (S == Strain::linear) {
            strain[a][b] = 0.5 * (H[a][b] + H[b][a]);
          } else {
            double C = 0.0;
            for (int c = 0; c < D; ++c) C += F[c][a] * F[c][b];
            strain[a][b] = 0.5 * (C - (a == b ? 1.0 : 0.0));
          }
        }
      double trace = 0.0, contraction = 0.0;
      for (int a = 0; a < D; ++a) trace += strain[a][a];
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          contraction += strain[a][b] * strain[a][b];
          stress[a][b] = (a == b ? kLambda * trace : 0.0) + 2.0 * kMu * strain[a][b];
        }
      W += w * (0.5 * kLambda * trace * trace + kMu * contraction);
      for (int a = 0; a < D; ++a)
        for (int b = 0; b < D; ++b) {
          P[a][b] = S == Strain::linear ? stress[a][b] : 0.0;
          if constexpr (S == Strain::green)
            for (int c = 0; c < D; ++c) P[a][b] += F[a][c] * stress[c][b];
        }
      if (gradient)
        for (int j = 0; j < N; ++j)
          for (int a = 0; a < D; ++a)
            for (int c = 0; c < D; ++c) (*gradient)[j * D + a] += w * P[a][c] * GT[c * N + j];
    }
    return W;
  }
};

/// Displacements of about `size` (a few per cent of the element).
std::vector<double> displacements(int dofs, double size, unsigned seed) {
  std::vector<double> u = pseudo_random(dofs, seed);
  for (double& value : u) value *= size;
  return u;
}

double largest_magnitude(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

/// The checks every case runs.
template <int D, int N, int Q, Strain S>
void check_element(const Reference<D, N, Q>& reference, const double (&nodes)[N][D]) {
  using E = Element<D, N, Q, S>;
  const E element(reference, rest_positions<D, N>(nodes, 7));
  constexpr int dofs = E::dofs;

  for (unsigned seed : {1u, 2u, 3u}) {
    SCOPED_TRACE(seed);
    const std::vector<double> u = displacements(dofs, 0.15, seed);
    std::vector<double> direct_gradient;
    const double direct_energy = element.direct(u, &direct_gradient);
    ASSERT_GT(direct_energy, 0.0);

    // Energy and gradient: the polynomial form equals the direct evaluation.
    EXPECT_NEAR(element.energy(u), direct_energy, 1e-12 * direct_energy);
    const std::vector<double> g = element.gradient(u);
    const double g_scale = largest_magnitude(direct_gradient);
    for (int i = 0; i < dofs; ++i) EXPECT_NEAR(g[i], direct_gradient[i], 1e-11 * g_scale) << "dof " << i;

    // Gradient and Hessian: central differences of the direct energy and gradient.
    const double h = 1e-6;
    const std::vector<double> K = element.hessian(u);
    const double K_scale = largest_magnitude(K);
    for (int j = 0; j < dofs; ++j) {
      std::vector<double> plus = u, minus = u;
      plus[j] += h;
      minus[j] -= h;
      std::vector<double> g_plus, g_minus;
      const double W_plus = element.direct(plus, &g_plus), W_minus = element.direct(minus, &g_minus);
      EXPECT_NEAR(g[j], (W_plus - W_minus) / (2 * h), 1e-7 * g_scale) << "dof " << j;
      for (int i = 0; i < dofs; ++i)
        EXPECT_NEAR(K[i * dofs + j], (g_plus[i] - g_minus[i]) / (2 * h), 1e-7 * K_scale) << i << ", " << j;
    }
    for (int i = 0; i < dofs; ++i)
      for (int j = 0; j < i; ++j) EXPECT_NEAR(K[i * dofs + j], K[j * dofs + i], 1e-13 * K_scale);
  }

  // At rest: no energy, no force, and the Hessian is K (the linear stiffness).
  const std::vector<double> zero(dofs, 0.0);
  EXPECT_EQ(element.energy(zero), 0.0);
  for (double value : element.gradient(zero)) EXPECT_EQ(value, 0.0);
  const std::vector<double> K0 = element.hessian(zero);
  for (int i = 0; i < dofs * dofs; ++i) EXPECT_EQ(K0[i], element.coefficients()[i]);
}

constexpr double kTri3Nodes[3][2] = {{0, 0}, {1, 0}, {0, 1}};
constexpr double kQuad4Nodes[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
constexpr double kTet4Nodes[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};

// --- Tables and layout -------------------------------------------------------

TEST(TensorSplit, NodePairsAreRowMajorWithMultiplicities) {
  constexpr auto& pairs = tensor::node_pairs<3>;
  static_assert(tensor::NodePairs<3>::count == 6);
  const int first[6] = {0, 0, 0, 1, 1, 2}, second[6] = {0, 1, 2, 1, 2, 2};
  for (int p = 0; p < 6; ++p) {
    EXPECT_EQ(pairs.first[p], first[p]);
    EXPECT_EQ(pairs.second[p], second[p]);
    EXPECT_EQ(pairs.multiplicity[p], first[p] == second[p] ? 1.0 : 2.0);
    EXPECT_EQ(pairs.of[first[p]][second[p]], p);
    EXPECT_EQ(pairs.of[second[p]][first[p]], p);
  }
}

TEST(TensorSplit, LayoutSizes) {
  using Tet4Green = tensor::Layout<3, 4, Strain::green>;
  static_assert(Tet4Green::k_size == 144 && Tet4Green::v_size == 4 * 10 * 3 && Tet4Green::d_size == 100);
  static_assert(Tet4Green::offset_v == 144 && Tet4Green::offset_d == 264 && Tet4Green::total == 364);
  using Tri3Linear = tensor::Layout<2, 3, Strain::linear>;
  static_assert(Tri3Linear::total == 36 && Tri3Linear::v_size == 0 && Tri3Linear::d_size == 0);
  using Hex8Green = tensor::Layout<3, 8, Strain::green>;
  static_assert(Hex8Green::total == 24 * 24 + 8 * 36 * 3 + 36 * 36);
  SUCCEED();
}

TEST(TensorSplit, PrecomputeRefusesAnInvertedElement) {
  const Reference<2, 3, 1> reference = tri3();
  const std::vector<double> inverted = {0, 0, 0, 1, 1, 0};  // nodes 1 and 2 swapped: det(J) < 0
  std::vector<double> consts(1 + 6 + tensor::Layout<2, 3, Strain::green>::total);
  const std::vector<double> CC = isotropic_elasticity<2>();
  EXPECT_EQ((tensor::precompute<2, 3, 1, Strain::green>(inverted.data(), reference.gradients, reference.weights,
                                                        CC.data(), consts.data())),
            1);
}

TEST(TensorSplit, LinearStiffnessOfAUnitTriangle) {
  // K of Hooke's law on the rest triangle (0,0), (1,0), (0,1) (area 1/2),
  // entry (node 1, x; node 1, x) = area (lambda + 2 mu) (dN1/dx)^2 = (lambda + 2 mu) / 2.
  const Reference<2, 3, 1> reference = tri3();
  const std::vector<double> X = {0, 0, 1, 0, 0, 1};
  std::vector<double> consts(1 + 6 + tensor::Layout<2, 3, Strain::linear>::total);
  const std::vector<double> CC = isotropic_elasticity<2>();
  ASSERT_EQ((tensor::precompute<2, 3, 1, Strain::linear>(X.data(), reference.gradients, reference.weights, CC.data(),
                                                         consts.data())),
            0);
  const double* K = consts.data() + 7;
  EXPECT_NEAR(K[2 * 6 + 2], 0.5 * (kLambda + 2 * kMu), 1e-15);
  EXPECT_NEAR(K[3 * 6 + 3], 0.5 * kMu, 1e-15);      // node 1, y; node 1, y: mu (dN1/dx)^2 area
  EXPECT_NEAR(K[2 * 6 + 5], 0.5 * kLambda, 1e-15);  // node 1, x; node 2, y: lambda dN1/dx dN2/dy area
  EXPECT_NEAR(K[3 * 6 + 4], 0.5 * kMu, 1e-15);      // node 1, y; node 2, x: mu dN1/dx dN2/dy area
}

// --- Energy, gradient and Hessian -------------------------------------------

TEST(TensorSplit, Tri3Hooke) { check_element<2, 3, 1, Strain::linear>(tri3(), kTri3Nodes); }
TEST(TensorSplit, Tri3StVK) { check_element<2, 3, 1, Strain::green>(tri3(), kTri3Nodes); }
TEST(TensorSplit, Quad4HookeFourPoints) { check_element<2, 4, 4, Strain::linear>(quad4(), kQuad4Nodes); }
TEST(TensorSplit, Quad4StVKFourPoints) { check_element<2, 4, 4, Strain::green>(quad4(), kQuad4Nodes); }
TEST(TensorSplit, Tet4Hooke) { check_element<3, 4, 1, Strain::linear>(tet4(), kTet4Nodes); }
TEST(TensorSplit, Tet4StVK) { check_element<3, 4, 1, Strain::green>(tet4(), kTet4Nodes); }

TEST(TensorSplit, StVKEnergyIsQuarticAlongARay) {
  // W(t u) = a t^2 + b t^3 + c t^4: its fourth difference at step 1 is 24 c
  // and the fifth vanishes.
  const Element<3, 4, 1, Strain::green> element(tet4(), rest_positions<3, 4>(kTet4Nodes, 11));
  const std::vector<double> u = displacements(12, 0.2, 5);
  std::array<double, 6> W{};
  for (int t = 0; t < 6; ++t) {
    std::vector<double> scaled = u;
    for (double& value : scaled) value *= t;
    W[t] = element.energy(scaled);
  }
  const double fifth = -W[0] + 5 * W[1] - 10 * W[2] + 10 * W[3] - 5 * W[4] + W[5];
  EXPECT_NEAR(fifth, 0.0, 1e-11 * W[5]);
  const double fourth = W[0] - 4 * W[1] + 6 * W[2] - 4 * W[3] + W[4];
  EXPECT_GT(fourth, 0.0);  // the quartic term s:D:s is positive
}

}  // namespace
