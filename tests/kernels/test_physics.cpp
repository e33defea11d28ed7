// The mechanics of the kernels: the laws agree at rest, the non-linear laws
// are invariant under rigid rotations (and Hooke is not), homogeneous
// deformations give the law's stress and energy density at every
// quadrature point (patch test of one element), the kernels write exactly
// their documented outputs, and precompute fills the documented constants
// and rejects inverted or degenerate (flat, collapsed, non-finite) elements.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "kernel_test_support.hpp"

namespace tmtest {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The second Piola-Kirchhoff stress S = lam tr(E) I + 2 mu E of a
/// symmetric strain E (3 by 3; lam, mu from the law files).
Matrix3 linear_stress(const Matrix3& E, double lam, double mu) {
  Matrix3 S{};
  const double trace = E[0] + E[4] + E[8];
  for (int i = 0; i < 9; ++i) S[i] = 2 * mu * E[i];
  for (int i = 0; i < 3; ++i) S[i * 4] += lam * trace;
  return S;
}

double contract(const Matrix3& a, const Matrix3& b) {
  double sum = 0.0;
  for (int i = 0; i < 9; ++i) sum += a[i] * b[i];
  return sum;
}

/// The rotation of F's polar decomposition, computed independently of the
/// kernels' Newton iteration: the eigenvectors V and eigenvalues of C = F^T F
/// by cyclic Jacobi rotations, U = V sqrt(L) V^T, R = F U^-1 (det F > 0).
Matrix3 polar_rotation_by_eigenvectors(const Matrix3& F) {
  Matrix3 C = multiply(transpose(F), F), V = identity3();
  for (int sweep = 0; sweep < 50; ++sweep) {
    const double off = C[1] * C[1] + C[2] * C[2] + C[5] * C[5];
    if (off < 1e-30 * (C[0] * C[0] + C[4] * C[4] + C[8] * C[8])) break;
    for (const auto& [p, q] : {std::pair{0, 1}, std::pair{0, 2}, std::pair{1, 2}}) {
      const double apq = C[p * 3 + q];
      if (apq == 0.0) continue;
      const double theta = 0.5 * std::atan2(2 * apq, C[q * 3 + q] - C[p * 3 + p]);
      const double c = std::cos(theta), s = std::sin(theta);
      Matrix3 J = identity3();  // C <- J^T C J zeroes C[p][q]
      J[p * 3 + p] = c;
      J[q * 3 + q] = c;
      J[p * 3 + q] = s;
      J[q * 3 + p] = -s;
      C = multiply(transpose(J), multiply(C, J));
      V = multiply(V, J);
    }
  }
  Matrix3 root{};
  for (int k = 0; k < 3; ++k) root[k * 4] = std::sqrt(C[k * 4]);
  return multiply(F, inverse(multiply(V, multiply(root, transpose(V)))));
}

/// The first Piola-Kirchhoff stress of `law` at F (3 by 3, F33 = 1 and no
/// coupling in 2D, where the laws are plane strain), written independently
/// of the generator from the formulas of laws/*.toml.
Matrix3 reference_piola(const std::string& law, const Matrix3& F, double lam, double mu) {
  if (law == "hooke") {
    Matrix3 eps{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) eps[i * 3 + j] = 0.5 * (F[i * 3 + j] + F[j * 3 + i]) - (i == j ? 1.0 : 0.0);
    return linear_stress(eps, lam, mu);
  }
  if (law == "stvk") {
    Matrix3 E = multiply(transpose(F), F);
    for (int i = 0; i < 3; ++i) E[i * 4] -= 1.0;
    for (double& e : E) e *= 0.5;
    return multiply(F, linear_stress(E, lam, mu));  // P = F S
  }
  if (law == "neohookean") {
    const double J = determinant(F);
    const Matrix3 inverse_transpose = transpose(inverse(F));
    Matrix3 P{};
    for (int i = 0; i < 9; ++i) P[i] = mu * (F[i] - inverse_transpose[i]) + lam * std::log(J) * inverse_transpose[i];
    return P;
  }
  if (law == "stable_neohookean") {  // mu' F (1 - 1/(I_C + 1)) + lam' (J - alpha) J F^-T
    const double mu_s = 4.0 / 3.0 * mu, lam_s = lam + 5.0 / 6.0 * mu, alpha = 1.0 + 0.75 * mu_s / lam_s;
    const double J = determinant(F), I_C = contract(F, F);
    const Matrix3 cofactor = transpose(inverse(F));  // times J below: J F^-T
    Matrix3 P{};
    for (int i = 0; i < 9; ++i) P[i] = mu_s * F[i] * (1.0 - 1.0 / (I_C + 1.0)) + lam_s * (J - alpha) * J * cofactor[i];
    return P;
  }
  if (law == "corotational") {  // P = 2 mu (F - R) + lam tr(S - I) R, S = R^T F
    const Matrix3 R = polar_rotation_by_eigenvectors(F);
    const Matrix3 S = multiply(transpose(R), F);
    const double trace = S[0] + S[4] + S[8] - 3.0;
    Matrix3 P{};
    for (int i = 0; i < 9; ++i) P[i] = 2 * mu * (F[i] - R[i]) + lam * trace * R[i];
    return P;
  }
  throw std::logic_error("no reference for law " + law);
}

/// The energy density of `law` at F (plane strain in 2D: d = dim).
double reference_density(const std::string& law, const Matrix3& F, double lam, double mu, int dim) {
  if (law == "hooke" || law == "stvk") {
    Matrix3 E{};
    if (law == "hooke") {
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) E[i * 3 + j] = 0.5 * (F[i * 3 + j] + F[j * 3 + i]) - (i == j ? 1.0 : 0.0);
    } else {
      E = multiply(transpose(F), F);
      for (int i = 0; i < 3; ++i) E[i * 4] -= 1.0;
      for (double& e : E) e *= 0.5;
    }
    const double trace = E[0] + E[4] + E[8];
    return 0.5 * lam * trace * trace + mu * contract(E, E);
  }
  if (law == "neohookean") {
    double I1 = 0.0;
    for (int i = 0; i < dim; ++i)
      for (int a = 0; a < dim; ++a) I1 += F[a * 3 + i] * F[a * 3 + i];
    const double log_J = std::log(determinant(F));
    return 0.5 * mu * (I1 - dim) - mu * log_J + 0.5 * lam * log_J * log_J;
  }
  if (law == "stable_neohookean") {  // Smith et al. 2018 with W(I) = 0; I_C is the 3D one (F33 = 1 in 2D)
    const double mu_s = 4.0 / 3.0 * mu, lam_s = lam + 5.0 / 6.0 * mu, alpha = 1.0 + 0.75 * mu_s / lam_s;
    const double J = determinant(F), I_C = contract(F, F);
    return 0.5 * mu_s * (I_C - 3.0) + 0.5 * lam_s * (J - alpha) * (J - alpha) -
           0.5 * mu_s * std::log((I_C + 1.0) / 4.0) - 0.5 * lam_s * (1.0 - alpha) * (1.0 - alpha);
  }
  if (law == "corotational") {  // mu |F - R|^2 + lam/2 tr(S - I)^2 (zero third row and column in 2D)
    const Matrix3 R = polar_rotation_by_eigenvectors(F);
    const Matrix3 S = multiply(transpose(R), F);
    Matrix3 difference{};
    for (int i = 0; i < 9; ++i) difference[i] = F[i] - R[i];
    const double trace = S[0] + S[4] + S[8] - 3.0;
    return mu * contract(difference, difference) + 0.5 * lam * trace * trace;
  }
  throw std::logic_error("no reference for law " + law);
}

/// An arbitrary deformation gradient: a rotation times a symmetric stretch
/// (det > 0), its third row and column those of I in 2D.
Matrix3 arbitrary_deformation(int dim, std::uint64_t seed, double amplitude) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Matrix3 U = identity3();
  for (int i = 0; i < 3; ++i)
    for (int j = i; j < 3; ++j) {
      const double value = amplitude * unit(random);
      U[i * 3 + j] += value;
      if (j != i) U[j * 3 + i] += value;
    }
  const Matrix3 R = dim == 3 ? rotation(1.0, -0.5, 2.0, 0.7) : rotation(0.0, 0.0, 1.0, 0.7);
  return embed(multiply(R, embed(U, dim)), dim);
}

Matrix3 rigid_rotation(int dim) {
  // 30 degrees about an oblique axis in 3D, about z in 2D.
  return dim == 3 ? rotation(1.0, 2.0, 3.0, kPi / 6) : rotation(0.0, 0.0, 1.0, kPi / 6);
}

/// The element volume: the sum of w det(J) over the points (ABI layout).
double element_volume(const Element& e) {
  const tm_kernel& k = *e.kernel;
  double volume = 0.0;
  for (int q = 0; q < k.quadrature_points; ++q)
    volume += e.consts[static_cast<std::size_t>(k.derived_params + q * (1 + k.dim * k.nodes))];
  return volume;
}

// --- Every kernel --------------------------------------------------------------

class KernelPhysics : public testing::TestWithParam<const tm_kernel*> {};

/// Under a rigid rotation u = (R - I) X the objective laws (stvk,
/// neohookean, corotational) have zero energy, force and stress; Hooke's small strain is
/// not rotation invariant and gives clearly non-zero forces.
TEST_P(KernelPhysics, RigidRotation) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 31);
  ASSERT_EQ(e.status, 0);
  Matrix3 stretch = identity3();
  stretch[0] = 1.1;  // a comparable 10 % stretch along x
  const Vector u_stretch = homogeneous_displacement(e, stretch);
  const Vector g_stretch = gradient(e, u_stretch);
  const double force_scale = max_abs(g_stretch);
  const double stress_scale = max_abs(stress(e, u_stretch));
  const double energy_scale = energy(e, u_stretch);
  ASSERT_GT(force_scale, 0.0);
  const Vector u = homogeneous_displacement(e, rigid_rotation(kernel.dim));
  const Vector g = gradient(e, u);
  if (std::string(kernel.law) == "hooke") {
    EXPECT_GT(max_abs(g), 0.1 * force_scale) << "Hooke's law should feel a rigid rotation (linear strain)";
    EXPECT_GT(energy(e, u), 0.1 * energy_scale);
  } else {
    EXPECT_LE(max_abs(g), 1e-10 * force_scale) << "forces under a rigid rotation";
    EXPECT_LE(std::abs(energy(e, u)), 1e-10 * energy_scale) << "energy under a rigid rotation";
    EXPECT_LE(max_abs(stress(e, u)), 1e-10 * stress_scale) << "stress under a rigid rotation";
  }
}

/// A homogeneous deformation u = (F - I) X is reproduced exactly by every
/// element: at every quadrature point the stress kernel returns the law's
/// first Piola-Kirchhoff stress at F (computed here independently: Hooke
/// sigma = lam tr(eps) I + 2 mu eps, StVK P = F S with E = (F^T F - I)/2,
/// neo-Hookean P = mu (F - F^-T) + lam ln(J) F^-T, corotational
/// P = 2 mu (F - R) + lam tr(R^T F - I) R with R from C's eigenvectors), and the energy is the
/// energy density times the element volume.
/// Whether reference_piola and reference_density know `law`.
bool has_reference_law(const std::string& law) {
  for (const char* known : {"hooke", "stvk", "neohookean", "stable_neohookean", "corotational"})
    if (law == known) return true;
  return false;
}

class ClosedFormLaw : public testing::TestWithParam<const tm_kernel*> {};

TEST_P(ClosedFormLaw, HomogeneousDeformationGivesLawStress) {
  const tm_kernel& kernel = *GetParam();
  const std::string law = kernel.law;
  const int dim = kernel.dim;
  for (const std::uint64_t seed : {41u, 42u, 43u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    const auto [lam, mu] = lame(e.params);
    const Matrix3 F = arbitrary_deformation(dim, seed, law == "hooke" ? 0.01 : 0.2);
    const Vector u = homogeneous_displacement(e, F);
    const Vector expected_point = block(reference_piola(law, F, lam, mu), dim);
    Vector expected;
    for (int q = 0; q < kernel.quadrature_points; ++q)
      expected.insert(expected.end(), expected_point.begin(), expected_point.end());
    EXPECT_LE(relative_error(stress(e, u), expected), 1e-10) << "stress at F";
    const double density = reference_density(law, F, lam, mu, dim);
    EXPECT_LE(relative_error(energy(e, u), density * element_volume(e)), 1e-10) << "energy at F";
  }
}

/// Precompute fills consts as documented: the derived parameters (lam, mu
/// for laws of young and poisson); per point w det(J) and
/// G^T with sum_j G_cj = 0 and sum_j X_aj G_cj = delta_ac (isoparametric
/// reproduction of a linear field); on the reference nodes w det(J) is the
/// element info's weight; on an affine shape the weights sum to the volume.
TEST_P(KernelPhysics, PrecomputeFillsDocumentedConstants) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = element_of(kernel);
  const int dim = kernel.dim, nodes = kernel.nodes, stride = 1 + dim * nodes;
  const int derived = kernel.derived_params;
  ASSERT_GE(kernel.consts, derived + kernel.quadrature_points * stride);
  ASSERT_EQ(kernel.quadrature_points, info.quadrature_points);

  std::mt19937_64 draw(62);
  const Vector params = has_elastic_parameters(kernel) ? Vector{2.5e5, 0.4} : material(kernel, draw);
  {  // the reference element itself: J = I
    Vector consts(static_cast<std::size_t>(kernel.consts));
    ASSERT_EQ(kernel.precompute(info.reference_nodes, params.data(), kernel.params, consts.data()), 0);
    if (has_elastic_parameters(kernel) && derived == 2) {
      const auto [lam, mu] = lame(params);
      EXPECT_LE(relative_error(consts[0], lam), 1e-14) << "consts[0] = lam";
      EXPECT_LE(relative_error(consts[1], mu), 1e-14) << "consts[1] = mu";
    }
    for (int q = 0; q < kernel.quadrature_points; ++q)
      EXPECT_LE(relative_error(consts[static_cast<std::size_t>(derived + q * stride)], info.weights[q]), 1e-14)
          << "w det(J) at point " << q;
  }
  for (const std::uint64_t seed : {61u, 62u}) {  // distorted shapes
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    for (int q = 0; q < kernel.quadrature_points; ++q) {
      const double* point = e.consts.data() + derived + q * stride;
      EXPECT_GT(point[0], 0.0);
      const double* GT = point + 1;
      double gradient_scale = 0.0;
      for (int i = 0; i < dim * nodes; ++i) gradient_scale = std::max(gradient_scale, std::abs(GT[i]));
      for (int c = 0; c < dim; ++c) {
        double sum = 0.0;
        for (int j = 0; j < nodes; ++j) sum += GT[c * nodes + j];
        EXPECT_LE(std::abs(sum), 1e-12 * gradient_scale) << "sum_j G at point " << q;
        for (int a = 0; a < dim; ++a) {
          double identity = 0.0;
          for (int j = 0; j < nodes; ++j) identity += e.rest[static_cast<std::size_t>(j * dim + a)] * GT[c * nodes + j];
          EXPECT_NEAR(identity, a == c ? 1.0 : 0.0, 1e-12) << "sum_j X G at point " << q;
        }
      }
    }
  }
  {  // affine shape: the volume is det(dX/dr) times the reference volume
    std::mt19937_64 random(63);
    double size = 0.0;
    Matrix3 map{};
    const Vector rest = rest_shape(info, random, &size, true, &map);
    Vector consts(static_cast<std::size_t>(kernel.consts));
    ASSERT_EQ(kernel.precompute(rest.data(), params.data(), kernel.params, consts.data()), 0);
    Element e;
    e.kernel = &kernel;
    e.consts = consts;
    EXPECT_LE(relative_error(element_volume(e), determinant(embed(map, dim)) * reference_volume(info.name)), 1e-12);
  }
}

/// Precompute refuses, before writing any constant, a parameter count other
/// than the kernel's and each parameter outside its limits or not finite.
TEST_P(KernelPhysics, PrecomputeRefusesWrongParameters) {
  const tm_kernel& kernel = *GetParam();
  const Element good = make_element(kernel, 71);
  ASSERT_EQ(good.status, 0);
  const Vector untouched(static_cast<std::size_t>(kernel.consts), -7.0);
  Vector consts = untouched;
  Vector longer = good.params;
  longer.push_back(1.0);
  EXPECT_EQ(kernel.precompute(good.rest.data(), longer.data(), kernel.params + 1, consts.data()),
            TM_PRECOMPUTE_PARAM_COUNT);
  EXPECT_EQ(kernel.precompute(good.rest.data(), good.params.data(), kernel.params - 1, consts.data()),
            TM_PRECOMPUTE_PARAM_COUNT);
  EXPECT_EQ(consts, untouched) << "constants written despite a wrong count";
  for (int p = 0; p < kernel.params; ++p) {
    SCOPED_TRACE(kernel.param_names[p]);
    const tm_param_limit& limit = kernel.param_limits[p];
    std::vector<double> outside = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()};
    if (std::isfinite(limit.lower))
      outside.push_back(limit.lower_inclusive ? std::nextafter(limit.lower, -1e300) : limit.lower);
    if (std::isfinite(limit.upper))
      outside.push_back(limit.upper_inclusive ? std::nextafter(limit.upper, 1e300) : limit.upper);
    for (const double value : outside) {
      Vector bad = good.params;
      bad[static_cast<std::size_t>(p)] = value;
      EXPECT_EQ(kernel.precompute(good.rest.data(), bad.data(), kernel.params, consts.data()),
                TM_PRECOMPUTE_BAD_PARAM - p)
          << "value " << value;
    }
  }
  EXPECT_EQ(consts, untouched) << "constants written despite a bad parameter";
}

/// An inverted (mirrored), a flat and a non-finite element are rejected at
/// the first quadrature point: precompute returns q + 1 = 1.
TEST_P(KernelPhysics, PrecomputeRejectsInvertedAndDegenerateElements) {
  const tm_kernel& kernel = *GetParam();
  const int dim = kernel.dim, nodes = kernel.nodes;
  const Element good = make_element(kernel, 71);
  ASSERT_EQ(good.status, 0);
  Vector consts(static_cast<std::size_t>(kernel.consts));

  Vector mirrored = good.rest;  // x -> -x: det(J) < 0 everywhere
  for (int j = 0; j < nodes; ++j) mirrored[static_cast<std::size_t>(j * dim)] *= -1.0;
  EXPECT_EQ(kernel.precompute(mirrored.data(), good.params.data(), kernel.params, consts.data()), 1) << "mirrored";

  Vector flat = good.rest;  // every node in the plane x_d = 0: det(J) = 0
  for (int j = 0; j < nodes; ++j) flat[static_cast<std::size_t>(j * dim + dim - 1)] = 0.0;
  EXPECT_EQ(kernel.precompute(flat.data(), good.params.data(), kernel.params, consts.data()), 1) << "flat";

  Vector collapsed(good.rest.size(), 0.0);  // every node at the origin: J = 0
  EXPECT_EQ(kernel.precompute(collapsed.data(), good.params.data(), kernel.params, consts.data()), 1) << "collapsed";

  Vector not_finite = good.rest;
  not_finite[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(kernel.precompute(not_finite.data(), good.params.data(), kernel.params, consts.data()), 1)
      << "NaN coordinate";
  not_finite[0] = std::numeric_limits<double>::infinity();
  EXPECT_GT(kernel.precompute(not_finite.data(), good.params.data(), kernel.params, consts.data()), 0)
      << "infinite coordinate";

  const std::string element = kernel.element;
  if (element == "tri3" || element == "tet4") {  // swapping two vertices of a simplex inverts it
    Vector swapped = good.rest;
    for (int a = 0; a < dim; ++a)
      std::swap(swapped[static_cast<std::size_t>(dim + a)], swapped[static_cast<std::size_t>(2 * dim + a)]);
    EXPECT_EQ(kernel.precompute(swapped.data(), good.params.data(), kernel.params, consts.data()), 1)
        << "two nodes swapped";
  }
  // The good shape is still accepted after the rejections.
  EXPECT_EQ(kernel.precompute(good.rest.data(), good.params.data(), kernel.params, consts.data()), 0);
  EXPECT_EQ(consts, good.consts);
}

/// A flat element in an oblique plane (every node projected onto the plane
/// through node 0 with a random normal) is degenerate: det(J) is zero up to
/// rounding (|det J| ~ 1e-16 of its scale), and precompute must reject it
/// like the axis-aligned flat element above, whatever the sign of the
/// rounding error.
TEST_P(KernelPhysics, PrecomputeRejectsObliqueFlatElements) {
  const tm_kernel& kernel = *GetParam();
  const int dim = kernel.dim, nodes = kernel.nodes, stride = 1 + dim * nodes;
  const double reference = reference_volume(kernel.element);
  std::string accepted;
  for (std::uint64_t seed = 1; seed <= 16; ++seed) {
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    std::mt19937_64 random(seed + 7000);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    double normal[3] = {unit(random), unit(random), dim == 3 ? unit(random) : 0.0}, length = 0.0;
    for (int a = 0; a < dim; ++a) length += normal[a] * normal[a];
    for (int a = 0; a < dim; ++a) normal[a] /= std::sqrt(length);
    Vector flat = e.rest;
    for (int j = 0; j < nodes; ++j) {
      double distance = 0.0;
      for (int a = 0; a < dim; ++a)
        distance += (e.rest[static_cast<std::size_t>(j * dim + a)] - e.rest[static_cast<std::size_t>(a)]) * normal[a];
      for (int a = 0; a < dim; ++a) flat[static_cast<std::size_t>(j * dim + a)] -= distance * normal[a];
    }
    Vector consts(static_cast<std::size_t>(kernel.consts));
    if (kernel.precompute(flat.data(), e.params.data(), kernel.params, consts.data()) == 0) {
      double smallest = 1e300;
      for (int q = 0; q < kernel.quadrature_points; ++q)
        smallest = std::min(smallest, consts[static_cast<std::size_t>(2 + q * stride)]);
      char line[96];
      std::snprintf(line, sizeof line, " seed %d (w det(J) / (size^d |ref|) = %.1e)", static_cast<int>(seed),
                    smallest / (std::pow(e.size, dim) * reference));
      accepted += line;
    }
  }
  EXPECT_TRUE(accepted.empty()) << "precompute accepted flat elements (returned 0):" << accepted;
}

/// Every kernel writes all of, and only, its documented output: consts
/// (`consts` doubles), gradient (dofs), hessian (dofs^2), stress (Q d^2).
/// The buffers start as NaN followed by a sentinel tail.
TEST_P(KernelPhysics, WritesExactlyTheDocumentedOutputs) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 75);
  ASSERT_EQ(e.status, 0);
  const Vector u = random_displacement(e, 76);
  constexpr double kSentinel = -12345.678;
  constexpr std::size_t kTail = 16;
  auto buffer = [&](int size) {
    Vector values(static_cast<std::size_t>(size), std::numeric_limits<double>::quiet_NaN());
    values.resize(values.size() + kTail, kSentinel);
    return values;
  };
  auto check = [&](const Vector& values, int size, const char* what) {
    for (int i = 0; i < size; ++i)
      EXPECT_TRUE(std::isfinite(values[static_cast<std::size_t>(i)])) << what << "[" << i << "] not written";
    for (std::size_t i = static_cast<std::size_t>(size); i < values.size(); ++i)
      EXPECT_EQ(values[i], kSentinel) << what << ": wrote past the end, at " << i;
  };
  const int dofs = kernel.dofs;
  Vector consts = buffer(kernel.consts);
  ASSERT_EQ(kernel.precompute(e.rest.data(), e.params.data(), kernel.params, consts.data()), 0);
  check(consts, kernel.consts, "consts");
  Vector g = buffer(dofs), K = buffer(dofs * dofs), P = buffer(kernel.quadrature_points * kernel.dim * kernel.dim);
  kernel.gradient(u.data(), consts.data(), g.data());
  check(g, dofs, "gradient");
  kernel.hessian(u.data(), consts.data(), K.data());
  check(K, dofs * dofs, "hessian");
  kernel.stress(u.data(), consts.data(), P.data());
  check(P, kernel.quadrature_points * kernel.dim * kernel.dim, "stress");
  g = buffer(dofs);
  K = buffer(dofs * dofs);
  kernel.gradient_hessian(u.data(), consts.data(), g.data(), K.data());
  check(g, dofs, "gradient_hessian gradient");
  check(K, dofs * dofs, "gradient_hessian hessian");
  EXPECT_TRUE(std::isfinite(kernel.energy(u.data(), consts.data())));
}

INSTANTIATE_TEST_SUITE_P(AllKernels, KernelPhysics, testing::ValuesIn(all_kernels()), KernelParamName());
// The other laws' stresses are held to their closed forms by tests/generator.
INSTANTIATE_TEST_SUITE_P(LawsWithAReference, ClosedFormLaw,
                         testing::ValuesIn(kernels_where([](const tm_kernel& k) { return has_reference_law(k.law); })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ClosedFormLaw);

// --- The objective (non-linear) laws -------------------------------------------

class ObjectiveLaw : public testing::TestWithParam<const tm_kernel*> {};

/// Objectivity of the non-linear laws: rotating a deformed state leaves the
/// energy unchanged and rotates every nodal force, W(R x) = W(x).
TEST_P(ObjectiveLaw, RotatedDeformedStateRotatesForces) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 32);
  ASSERT_EQ(e.status, 0);
  const int dim = kernel.dim, nodes = kernel.nodes;
  const Vector u = random_displacement(e, 33, 0.08, 0.01);
  const Matrix3 R = rigid_rotation(dim);
  Vector u_rotated(u.size());  // x' = R x  =>  u' = R (X + u) - X
  for (int j = 0; j < nodes; ++j)
    for (int a = 0; a < dim; ++a) {
      double value = -e.rest[static_cast<std::size_t>(j * dim + a)];
      for (int c = 0; c < dim; ++c) {
        const auto index = static_cast<std::size_t>(j * dim + c);
        value += R[a * 3 + c] * (e.rest[index] + u[index]);
      }
      u_rotated[static_cast<std::size_t>(j * dim + a)] = value;
    }
  EXPECT_LE(relative_error(energy(e, u_rotated), energy(e, u)), 1e-10);
  const Vector g = gradient(e, u);
  Vector g_expected(g.size());
  for (int j = 0; j < nodes; ++j)
    for (int a = 0; a < dim; ++a) {
      double value = 0.0;
      for (int c = 0; c < dim; ++c) value += R[a * 3 + c] * g[static_cast<std::size_t>(j * dim + c)];
      g_expected[static_cast<std::size_t>(j * dim + a)] = value;
    }
  EXPECT_LE(relative_error(gradient(e, u_rotated), g_expected), 1e-10);
}

INSTANTIATE_TEST_SUITE_P(AllButHooke, ObjectiveLaw, testing::ValuesIn(kernels_where([](const tm_kernel& k) {
                           return std::string(k.law) != "hooke";
                         })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(ObjectiveLaw);

// --- Invertible laws: defined and restoring through inversion ---------------

class InvertibleLaw : public testing::TestWithParam<const tm_kernel*> {};

/// An element flipped along x (F = diag(-1/2, 1, 1)): energy, forces and
/// tangent are finite, the energy is above the rest state's, and P_xx < 0 at
/// every point, so the forces push the element back to a positive volume.
TEST_P(InvertibleLaw, InvertedElementIsPushedBack) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 61);
  ASSERT_EQ(e.status, 0);
  Matrix3 flip = identity3();
  flip[0] = -0.5;
  const Vector u = homogeneous_displacement(e, flip);
  const double W = energy(e, u);
  EXPECT_TRUE(std::isfinite(W));
  EXPECT_GT(W, 0.0);
  for (const double g : gradient(e, u)) EXPECT_TRUE(std::isfinite(g));
  for (const double k : hessian(e, u)) EXPECT_TRUE(std::isfinite(k));
  const Vector P = stress(e, u);
  for (int q = 0; q < kernel.quadrature_points; ++q)
    EXPECT_LT(P[static_cast<std::size_t>(q * kernel.dim * kernel.dim)], 0.0);
}

INSTANTIATE_TEST_SUITE_P(Flagged, InvertibleLaw,
                         testing::ValuesIn(kernels_where([](const tm_kernel& k) { return k.invertible != 0; })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(InvertibleLaw);

// --- Hooke: uniform strain on one distorted element, a quadratic energy -----

class HookeLaw : public testing::TestWithParam<const tm_kernel*> {};

/// u = (eps + omega) X with a constant small symmetric strain eps and an
/// infinitesimal rotation omega: at every quadrature point of a distorted
/// element sigma = lam tr(eps) I + 2 mu eps.
TEST_P(HookeLaw, UniformStrainGivesHookeStress) {
  const tm_kernel& kernel = *GetParam();
  const int dim = kernel.dim;
  for (const std::uint64_t seed : {81u, 82u, 83u}) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    const Element e = make_element(kernel, seed);
    ASSERT_EQ(e.status, 0);
    const auto [lam, mu] = lame(e.params);
    std::mt19937_64 random(seed + 1000);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    Matrix3 eps{}, F = identity3();
    for (int i = 0; i < dim; ++i)
      for (int j = i; j < dim; ++j) {
        const double strain = 0.01 * unit(random), spin = i == j ? 0.0 : 0.01 * unit(random);
        eps[i * 3 + j] = eps[j * 3 + i] = strain;
        F[i * 3 + j] += strain + spin;
        if (i != j) F[j * 3 + i] += strain - spin;
      }
    const Vector expected_point = block(linear_stress(eps, lam, mu), dim);
    Vector expected;
    for (int q = 0; q < kernel.quadrature_points; ++q)
      expected.insert(expected.end(), expected_point.begin(), expected_point.end());
    EXPECT_LE(relative_error(stress(e, homogeneous_displacement(e, F)), expected), 1e-10);
  }
}

/// Hooke is quadratic: g = K u, W = u.K u / 2 for any u (what the `linear`
/// flag promises; the assembler folds such cells into one constant matrix).
TEST_P(HookeLaw, HookeIsQuadratic) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 51);
  ASSERT_EQ(e.status, 0);
  const Vector u = random_displacement(e, 52);
  const Vector K = hessian(e, random_displacement(e, 53));
  EXPECT_LE(relative_error(K, hessian(e, Vector(u.size(), 0.0))), 1e-12) << "constant Hessian";
  const std::size_t dofs = u.size();
  Vector Ku(dofs, 0.0);
  double uKu = 0.0;
  for (std::size_t i = 0; i < dofs; ++i) {
    for (std::size_t j = 0; j < dofs; ++j) Ku[i] += K[i * dofs + j] * u[j];
    uKu += u[i] * Ku[i];
  }
  EXPECT_LE(relative_error(gradient(e, u), Ku), 1e-12);
  EXPECT_LE(relative_error(energy(e, u), 0.5 * uKu), 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Hooke, HookeLaw, testing::ValuesIn(kernels_where([](const tm_kernel& k) {
                           return std::string(k.law) == "hooke";
                         })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(HookeLaw);

class NonlinearLaw : public testing::TestWithParam<const tm_kernel*> {};

/// A kernel flagged non-linear really is: at a finite displacement its force
/// differs from K(0) u (so folding it into a constant matrix would be wrong).
TEST_P(NonlinearLaw, GradientIsNotTheRestHessianTimesU) {
  const tm_kernel& kernel = *GetParam();
  const Element e = make_element(kernel, 54);
  ASSERT_EQ(e.status, 0);
  const Vector u = random_displacement(e, 55, 0.3);  // strains of tenths: the quadratic terms show
  const Vector K = hessian(e, Vector(u.size(), 0.0));
  const std::size_t dofs = u.size();
  Vector Ku(dofs, 0.0);
  for (std::size_t i = 0; i < dofs; ++i)
    for (std::size_t j = 0; j < dofs; ++j) Ku[i] += K[i * dofs + j] * u[j];
  EXPECT_GT(relative_error(gradient(e, u), Ku), 1e-3);
}

INSTANTIATE_TEST_SUITE_P(Flagged, NonlinearLaw,
                         testing::ValuesIn(kernels_where([](const tm_kernel& k) { return k.linear == 0; })),
                         KernelParamName());
// Empty for a registry without such kernels (a scratch project).
GTEST_ALLOW_UNINSTANTIATED_PARAMETERIZED_TEST(NonlinearLaw);

// --- One element type, every law at rest ------------------------------------

class LawsAtRest : public testing::TestWithParam<std::string> {};

/// At u = 0 every law is at rest: zero energy, gradient and stress; a law of
/// young and poisson linearises to Hooke's with them (the same Hessian, all
/// splits but fbar, whose laws linearise to Hooke's fbar kernel: B-bar);
/// each such law of the registry has a whole kernel on the element.
TEST_P(LawsAtRest, HessiansEqualHookeAndGradientIsZero) {
  const std::string& element = GetParam();
  const tm_kernel* hooke = registry().find("hooke", element, "whole");
  ASSERT_NE(hooke, nullptr);
  const Element reference = make_element(*hooke, 91);
  ASSERT_EQ(reference.status, 0);
  const Vector zero(reference.rest.size(), 0.0);
  const Vector K_whole = hessian(reference, zero);
  // Laws linearise to Hooke's kernel of their mean-dilatation form: fbar's,
  // and anp's where it builds on fbar (several points: prism6).
  const tm_kernel* hooke_fbar = registry().find("hooke", element, "fbar");
  if (!hooke_fbar && registry().find("hooke", element, "anp") && hooke->quadrature_points > 1)
    hooke_fbar = registry().find("hooke", element, "anp");
  const Vector K_fbar = hooke_fbar ? hessian(make_element(*hooke_fbar, 91), zero) : Vector();
  std::set<std::string> elastic_laws, elastic_laws_here;
  for (const tm_kernel* kernel : registry().kernels())
    if (has_elastic_parameters(*kernel)) elastic_laws.insert(kernel->law);
  for (const tm_kernel* kernel : registry().kernels()) {
    if (kernel->element != element) continue;
    SCOPED_TRACE(kernel_name(*kernel));
    const Element e = make_element(*kernel, 91);  // same shape (and material, for laws of young and poisson)
    ASSERT_EQ(e.status, 0);
    const Vector K = hessian(e, zero);
    const double force_scale = max_abs(K) * e.size;  // force of a unit strain
    if (has_elastic_parameters(*kernel)) {
      if (std::string(kernel->split) == "whole") elastic_laws_here.insert(kernel->law);
      const bool fbar = std::string(kernel->split) == "fbar" ||
                        (std::string(kernel->split) == "anp" && kernel->quadrature_points > 1);
      EXPECT_LE(relative_error(K, fbar ? K_fbar : K_whole), 1e-10) << "Hessian at rest";
    }
    EXPECT_LE(max_abs(gradient(e, zero)), 1e-12 * force_scale) << "gradient at rest";
    EXPECT_LE(std::abs(energy(e, zero)), 1e-12 * force_scale * e.size) << "energy at rest";
    EXPECT_LE(max_abs(stress(e, zero)), 1e-12 * stress_scale(K, e.size, kernel->dim)) << "stress at rest";
  }
  EXPECT_EQ(elastic_laws_here, elastic_laws);
}

INSTANTIATE_TEST_SUITE_P(AllElements, LawsAtRest, testing::ValuesIn(element_names()), ElementParamName());

}  // namespace
}  // namespace tmtest
