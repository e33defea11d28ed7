// Criteria of the adaptive model (criteria.hpp) on hand-built elements with
// known values, on every element type and kernel of the registry, and their
// cost per element.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "allocation_counter.hpp"
#include "tensormass/adaptivity/criteria.hpp"
#include "tensormass/kernels/law_parameters.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

using Matrix = std::array<std::array<double, 3>, 3>;
using Vector = std::array<double, 3>;

const Registry& registry() { return Registry::instance(); }

// --- Test elements -------------------------------------------------------------

/// The test elements' material (make_element) and its Lame parameters.
constexpr double kYoung = 1.0e6, kPoisson = 0.3;
constexpr double kLam = kYoung * kPoisson / ((1 + kPoisson) * (1 - 2 * kPoisson));
constexpr double kMu = kYoung / (2 * (1 + kPoisson));

/// One element with its own constants, rest positions, displacements and forces.
struct TestElement {
  const tm_kernel* kernel;
  const tm_element_info* info;
  std::vector<double> rest, consts, u, force;

  int dim() const { return kernel->dim; }
  int nodes() const { return kernel->nodes; }
  ElementView view() const {
    return {*info, *kernel, consts.data(), rest.data(), u.data(), force.data(), kernel->dim, kYoung};
  }
  double value(const std::string& criterion) const { return make_criterion(criterion)->evaluate(view()); }
};

TestElement make_element(const tm_kernel& kernel, std::vector<double> rest) {
  TestElement element{&kernel, registry().element(kernel.element), std::move(rest), {}, {}, {}};
  element.consts.assign(kernel.consts, 0.0);
  // kYoung, kPoisson for laws of young and poisson; the criteria of other laws read geometry only.
  const std::vector<double> params = tensormass::parameter_names(kernel) == std::vector<std::string>{"young", "poisson"}
                                         ? std::vector<double>{kYoung, kPoisson}
                                         : tensormass::admissible_parameters(kernel);
  if (kernel.precompute(element.rest.data(), params.data(), kernel.params, element.consts.data()) != 0)
    throw std::runtime_error(std::string("non-positive rest Jacobian for ") + kernel.element);
  element.u.assign(element.rest.size(), 0.0);
  element.force.assign(element.rest.size(), 0.0);
  return element;
}

TestElement make_element(const std::string& type, std::vector<double> rest) {
  return make_element(registry().get("hooke", type, "whole"), std::move(rest));
}

std::vector<double> reference_nodes(const tm_element_info& info) {
  return {info.reference_nodes, info.reference_nodes + info.nodes * info.dim};
}

/// Rest positions A x of the reference nodes x.
std::vector<double> mapped_reference_nodes(const tm_element_info& info, const Matrix& A) {
  std::vector<double> rest = reference_nodes(info);
  const int d = info.dim;
  for (int j = 0; j < info.nodes; ++j) {
    Vector x{};
    for (int a = 0; a < d; ++a)
      for (int c = 0; c < d; ++c) x[a] += A[a][c] * info.reference_nodes[j * d + c];
    for (int a = 0; a < d; ++a) rest[j * d + a] = x[a];
  }
  return rest;
}

/// u = (A - I) x on the rest positions x: the element becomes A x.
void deform_affine(TestElement& element, const Matrix& A) {
  const int d = element.dim();
  for (int j = 0; j < element.nodes(); ++j)
    for (int a = 0; a < d; ++a) {
      double sum = -element.rest[j * d + a];
      for (int c = 0; c < d; ++c) sum += A[a][c] * element.rest[j * d + c];
      element.u[j * d + a] = sum;
    }
}

void set_all_forces(TestElement& element, const Vector& f) {
  for (int j = 0; j < element.nodes(); ++j)
    for (int a = 0; a < element.dim(); ++a) element.force[j * element.dim() + a] = f[a];
}

// --- Small linear algebra --------------------------------------------------------

Matrix diagonal(double x, double y, double z) { return {{{x, 0, 0}, {0, y, 0}, {0, 0, z}}}; }

Matrix stretch_x(double s) { return diagonal(s, 1, 1); }

Matrix scaled(const Matrix& A, double s) {
  Matrix result = A;
  for (auto& row : result)
    for (double& entry : row) entry *= s;
  return result;
}

/// Rotation by theta about the unit `axis` (Rodrigues); axis z gives the 2D rotation.
Matrix rotation(double theta, Vector axis = {0, 0, 1}) {
  const double norm = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
  for (double& c : axis) c /= norm;
  const double cs = std::cos(theta), sn = std::sin(theta);
  const Matrix K{{{0, -axis[2], axis[1]}, {axis[2], 0, -axis[0]}, {-axis[1], axis[0], 0}}};
  Matrix R{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) R[a][b] = (a == b ? cs : 0.0) + sn * K[a][b] + (1 - cs) * axis[a] * axis[b];
  return R;
}

double determinant(const Matrix& A, int dim) {
  if (dim == 2) return A[0][0] * A[1][1] - A[0][1] * A[1][0];
  return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
         A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
}

/// |1/2 H^T H|_F with H = A - I (the first dim by dim block).
double quadratic_strain_norm(const Matrix& A, int dim) {
  double squared = 0.0;
  for (int c = 0; c < dim; ++c)
    for (int e = 0; e < dim; ++e) {
      double entry = 0.0;
      for (int a = 0; a < dim; ++a) entry += (A[a][c] - (a == c)) * (A[a][e] - (a == e));
      squared += entry * entry;
    }
  return 0.5 * std::sqrt(squared);
}

/// |E|_F of E = (A^T A - I) / 2, written from A itself (not through H).
double green_strain_norm(const Matrix& A, int dim) {
  double squared = 0.0;
  for (int c = 0; c < dim; ++c)
    for (int e = 0; e < dim; ++e) {
      double entry = c == e ? -1.0 : 0.0;
      for (int a = 0; a < dim; ++a) entry += A[a][c] * A[a][e];
      squared += 0.25 * entry * entry;
    }
  return std::sqrt(squared);
}

/// The first dim by dim block of A B.
Matrix product(const Matrix& A, const Matrix& B, int dim) {
  Matrix C{};
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b)
      for (int c = 0; c < dim; ++c) C[a][b] += A[a][c] * B[c][b];
  return C;
}

/// lam tr(S) I + 2 mu S for a symmetric S (dim by dim).
Matrix isotropic(const Matrix& S, int dim) {
  double trace = 0.0;
  for (int a = 0; a < dim; ++a) trace += S[a][a];
  Matrix result{};
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) result[a][b] = 2 * kMu * S[a][b] + (a == b ? kLam * trace : 0.0);
  return result;
}

/// Hooke's stress at F = A: sigma(eps), eps = sym(A) - I.
Matrix hooke_stress(const Matrix& A, int dim) {
  Matrix eps{};
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) eps[a][b] = 0.5 * (A[a][b] + A[b][a]) - (a == b);
  return isotropic(eps, dim);
}

/// St Venant-Kirchhoff: P = F S(E), E = (F^T F - I) / 2.
Matrix stvk_stress(const Matrix& A, int dim) {
  Matrix E{};
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) {
      E[a][b] = a == b ? -0.5 : 0.0;
      for (int c = 0; c < dim; ++c) E[a][b] += 0.5 * A[c][a] * A[c][b];
    }
  return product(A, isotropic(E, dim), dim);
}

/// Compressible neo-Hookean: P = mu (F - F^-T) + lam ln J F^-T.
Matrix neohookean_stress(const Matrix& A, int dim) {
  const double J = determinant(A, dim);
  Matrix inverse_t{};  // the cofactor matrix over J
  if (dim == 2) {
    inverse_t = {{{A[1][1] / J, -A[1][0] / J, 0}, {-A[0][1] / J, A[0][0] / J, 0}, {0, 0, 0}}};
  } else {
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) {
        const int a1 = (a + 1) % 3, a2 = (a + 2) % 3, b1 = (b + 1) % 3, b2 = (b + 2) % 3;
        inverse_t[a][b] = (A[a1][b1] * A[a2][b2] - A[a1][b2] * A[a2][b1]) / J;
      }
  }
  Matrix P{};
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) P[a][b] = kMu * (A[a][b] - inverse_t[a][b]) + kLam * std::log(J) * inverse_t[a][b];
  return P;
}

/// |P - Q|_F / E: R_P under an affine deformation (every point alike).
double stress_error(const Matrix& P, const Matrix& Q, int dim) {
  double squared = 0.0;
  for (int a = 0; a < dim; ++a)
    for (int b = 0; b < dim; ++b) squared += (P[a][b] - Q[a][b]) * (P[a][b] - Q[a][b]);
  return std::sqrt(squared) / kYoung;
}

// --- Geometry computed by the tests ------------------------------------------------

double node_distance(const TestElement& element, bool deformed, int a, int b) {
  const int d = element.dim();
  double squared = 0.0;
  for (int c = 0; c < d; ++c) {
    double delta = element.rest[b * d + c] - element.rest[a * d + c];
    if (deformed) delta += element.u[b * d + c] - element.u[a * d + c];
    squared += delta * delta;
  }
  return std::sqrt(squared);
}

double mean_edge(const TestElement& element, bool deformed) {
  double sum = 0.0;
  for (int e = 0; e < element.info->edge_count; ++e) {
    const int* edge = element.info->edges + e * element.info->edge_size;
    sum += node_distance(element, deformed, edge[0], edge[1]);
  }
  return sum / element.info->edge_count;
}

double max_edge_strain(const TestElement& element) {
  double largest = 0.0;
  for (int e = 0; e < element.info->edge_count; ++e) {
    const int* edge = element.info->edges + e * element.info->edge_size;
    const double rest = node_distance(element, false, edge[0], edge[1]);
    largest = std::max(largest, std::fabs(node_distance(element, true, edge[0], edge[1]) - rest) / rest);
  }
  return largest;
}

/// The measure of the reference element (area in 2D), from its element file.
double reference_volume(const std::string& type) { return registry().element(type)->reference_volume; }

// --- Hand-built shapes ---------------------------------------------------------------

/// Regular tetrahedron of edge 1, positively oriented.
std::vector<double> regular_tet() {
  const double h = std::sqrt(3.0);
  return {0, 0, 0, 1, 0, 0, 0.5, h / 2, 0, 0.5, h / 6, std::sqrt(2.0 / 3.0)};
}

std::vector<double> equilateral_triangle() { return {0, 0, 1, 0, 0.5, std::sqrt(3.0) / 2}; }

/// Axis-aligned boxes [0,2] x [0,1] (x [0,3]) in reference node order.
std::vector<double> box(const std::string& type) {
  const tm_element_info& info = *registry().element(type);
  std::vector<double> rest = reference_nodes(info);
  const double size[3] = {2.0, 1.0, 3.0};
  for (int j = 0; j < info.nodes; ++j)
    for (int c = 0; c < info.dim; ++c) rest[j * info.dim + c] = (rest[j * info.dim + c] + 1) / 2 * size[c];
  return rest;
}

constexpr double kTight = 1e-12;

// --- Names, flags, thresholds ----------------------------------------------------------

TEST(CriteriaNames, AreTheEightInOrderAndEachMakesItsCriterion) {
  const std::vector<std::string> expected{"R_EL", "R_V", "R_VL", "R_VLX", "R_S", "R_NL", "R_E", "R_P"};
  EXPECT_EQ(criterion_names(), expected);
  for (const std::string& name : criterion_names()) EXPECT_EQ(make_criterion(name)->name(), name);
}

TEST(CriteriaNames, UnknownNameThrowsInvalidArgument) {
  EXPECT_THROW(make_criterion("nope"), std::invalid_argument);
  EXPECT_THROW(make_criterion("r_el"), std::invalid_argument);
  EXPECT_THROW(make_criterion(""), std::invalid_argument);
}

TEST(CriteriaFlags, QualityAndForceFlags) {
  for (const std::string& name : criterion_names()) {
    const auto criterion = make_criterion(name);
    EXPECT_EQ(criterion->is_quality(), name == "R_VL" || name == "R_VLX") << name;
    EXPECT_EQ(criterion->needs_force(), name == "R_S") << name;
  }
}

/// Quality criteria fail strictly below the threshold, the others at or
/// above it (so a threshold of 0 fails every cell, even one at rest).
TEST(CriteriaFlags, QualityFailsBelowThresholdOthersAtOrAbove) {
  for (const std::string& name : criterion_names()) {
    const auto criterion = make_criterion(name);
    const bool quality = criterion->is_quality();
    EXPECT_EQ(criterion->fails(0.1, 0.2), quality) << name;
    EXPECT_EQ(criterion->fails(0.3, 0.2), !quality) << name;
    EXPECT_EQ(criterion->fails(0.2, 0.2), !quality) << name;
    EXPECT_EQ(criterion->fails(0.0, 0.0), !quality) << name;
  }
}

// --- Rest state ------------------------------------------------------------------------

TEST(CriteriaAtRest, RegularTet) {
  const TestElement tet = make_element("tet4", regular_tet());
  EXPECT_EQ(tet.value("R_EL"), 0.0);
  EXPECT_EQ(tet.value("R_V"), 0.0);
  EXPECT_EQ(tet.value("R_NL"), 0.0);
  EXPECT_EQ(tet.value("R_E"), 0.0);
  EXPECT_EQ(tet.value("R_S"), 0.0);
  EXPECT_NEAR(tet.value("R_VL"), 1.0 / (6.0 * std::sqrt(2.0)), kTight);
  EXPECT_NEAR(tet.value("R_VLX"), 1.0, kTight);
}

TEST(CriteriaAtRest, EquilateralTriangle) {
  const TestElement tri = make_element("tri3", equilateral_triangle());
  EXPECT_EQ(tri.value("R_EL"), 0.0);
  EXPECT_EQ(tri.value("R_V"), 0.0);
  EXPECT_EQ(tri.value("R_NL"), 0.0);
  EXPECT_NEAR(tri.value("R_VL"), std::sqrt(3.0) / 4.0, kTight);
  EXPECT_NEAR(tri.value("R_VLX"), 1.0, kTight);
}

TEST(CriteriaAtRest, BoxesQualityFromVolumeAndMeanEdge) {
  // hex8 2 x 1 x 3: v = 6, mean edge = (4*2 + 4*1 + 4*3) / 12 = 2, l_harm = 12 / (4/2 + 4 + 4/3).
  const TestElement hex = make_element("hex8", box("hex8"));
  EXPECT_NEAR(hex.value("R_VL"), 6.0 / 8.0, kTight);
  EXPECT_NEAR(hex.value("R_VLX"), 6 * std::sqrt(2.0) * 6.0 * (12.0 / (2.0 + 4.0 + 4.0 / 3.0)) / 16.0, kTight);
  // quad4 2 x 1: a = 2, mean edge = 1.5, l_harm = 4 / (2/2 + 2) = 4/3.
  const TestElement quad = make_element("quad4", box("quad4"));
  EXPECT_NEAR(quad.value("R_VL"), 2.0 / 2.25, kTight);
  EXPECT_NEAR(quad.value("R_VLX"), 4 / std::sqrt(3.0) * 2.0 * (4.0 / 3.0) / 3.375, kTight);
}

// --- Uniform stretch along x -----------------------------------------------------------

class CriteriaStretch : public ::testing::TestWithParam<double> {};

TEST_P(CriteriaStretch, BoxesGiveStretchStrainVolumeAndQuadraticPart) {
  const double s = GetParam();
  for (const std::string type : {"hex8", "quad4"}) {
    TestElement element = make_element(type, box(type));
    deform_affine(element, stretch_x(s));
    EXPECT_NEAR(element.value("R_EL"), std::fabs(s - 1), kTight) << type;
    EXPECT_NEAR(element.value("R_V"), std::fabs(s - 1), kTight) << type;
    EXPECT_NEAR(element.value("R_NL"), (s - 1) * (s - 1) / 2, kTight) << type;
    EXPECT_NEAR(element.value("R_E"), std::fabs(s * s - 1) / 2, kTight) << type;
  }
}

TEST_P(CriteriaStretch, RegularTetVolumeAndQuadraticPart) {
  const double s = GetParam();
  TestElement tet = make_element("tet4", regular_tet());
  deform_affine(tet, stretch_x(s));
  EXPECT_NEAR(tet.value("R_V"), std::fabs(s - 1), kTight);
  EXPECT_NEAR(tet.value("R_NL"), (s - 1) * (s - 1) / 2, kTight);
  EXPECT_NEAR(tet.value("R_EL"), max_edge_strain(tet), kTight);
  EXPECT_NEAR(tet.value("R_VL"), s / (6 * std::sqrt(2.0)) / std::pow(mean_edge(tet, true), 3), kTight);
}

INSTANTIATE_TEST_SUITE_P(Factors, CriteriaStretch, ::testing::Values(1.3, 0.6, 2.5));

// --- Rigid rotation ------------------------------------------------------------------------

TEST(CriteriaRotation, LargeRotationKeepsLengthsVolumesQualityButNotTheQuadraticPart) {
  const double theta = 1.2;
  const Vector axis{1.0, -2.0, 0.5};
  for (const std::string type : {"tri3", "quad4", "tet4", "hex8"}) {
    TestElement element = make_element(type, type == "tet4" ? regular_tet() : box(type));
    const double vl = element.value("R_VL"), vlx = element.value("R_VLX");
    const int dim = element.dim();
    deform_affine(element, dim == 2 ? rotation(theta) : rotation(theta, axis));
    EXPECT_NEAR(element.value("R_EL"), 0.0, kTight) << type;
    EXPECT_NEAR(element.value("R_V"), 0.0, kTight) << type;
    // 1/2 H^T H = I - sym(R) = (1 - cos theta) (I - n n^T): two unit eigenvalues in 2D and 3D.
    EXPECT_NEAR(element.value("R_NL"), std::sqrt(2.0) * (1 - std::cos(theta)), kTight) << type;
    EXPECT_NEAR(element.value("R_E"), 0.0, kTight) << type << ": the rotation-free strain";
    EXPECT_NEAR(element.value("R_VL"), vl, kTight) << type;
    EXPECT_NEAR(element.value("R_VLX"), vlx, kTight) << type;
  }
}

// --- Flattening ------------------------------------------------------------------------------

TEST(CriteriaFlattening, ApexTowardBaseDropsQualityAndVolumeRatioGoesToOne) {
  const std::vector<double> rest = regular_tet();
  const double height = rest[11];
  double previous_vl = 1.0, previous_vlx = 2.0;
  for (double t : {0.5, 0.1, 0.01, 1e-4}) {  // apex height becomes t * height
    TestElement tet = make_element("tet4", rest);
    tet.u[11] = (t - 1) * height;
    EXPECT_NEAR(tet.value("R_V"), 1 - t, kTight);
    EXPECT_LT(tet.value("R_VL"), previous_vl);
    EXPECT_LT(tet.value("R_VLX"), previous_vlx);
    previous_vl = tet.value("R_VL");
    previous_vlx = tet.value("R_VLX");
  }
  EXPECT_LT(previous_vl, 1e-4);
  EXPECT_LT(previous_vlx, 1e-3);
  EXPECT_TRUE(make_criterion("R_VLX")->fails(previous_vlx, 0.3));
}

TEST(CriteriaFlattening, InvertedTetHasNegativeQualityAndInfiniteStress) {
  TestElement tet = make_element("tet4", regular_tet());
  tet.u[11] = -2 * tet.rest[11];  // apex mirrored through the base
  EXPECT_NEAR(tet.value("R_V"), 2.0, kTight);
  EXPECT_LT(tet.value("R_VL"), 0.0);
  EXPECT_LT(tet.value("R_VLX"), 0.0);
  EXPECT_TRUE(std::isinf(tet.value("R_S")));
}

// --- R_S ------------------------------------------------------------------------------------------

TEST(CriteriaStress, ZeroForceGivesZero) {
  for (const tm_element_info* info : registry().elements()) {
    TestElement element = make_element(info->name, reference_nodes(*info));
    deform_affine(element, stretch_x(1.4));
    EXPECT_EQ(element.value("R_S"), 0.0) << info->name;
  }
}

TEST(CriteriaStress, ConstantForceGivesItsNormTimesRestOverDeformedVolume) {
  const Vector f{3.0, -4.0, 12.0};  // |f| = 13 in 3D, 5 in 2D
  for (const std::string type : {"tet4", "hex8", "quad4"}) {
    TestElement element = make_element(type, type == "tet4" ? regular_tet() : box(type));
    set_all_forces(element, f);
    const double norm = element.dim() == 3 ? 13.0 : 5.0;
    EXPECT_NEAR(element.value("R_S"), norm, kTight * norm) << type;
    deform_affine(element, stretch_x(1.6));
    EXPECT_NEAR(element.value("R_S"), norm / 1.6, kTight * norm) << type;
  }
}

/// Nodal forces f_j = (j + 1, (j * 7) % 5 - 2, 1 - j) and their weighted sum.
Vector varied_forces(TestElement& element, const std::vector<double>& integrals_of_N) {
  Vector expected{};
  for (int j = 0; j < element.nodes(); ++j) {
    const Vector f{j + 1.0, (j * 7) % 5 - 2.0, 1.0 - j};
    for (int a = 0; a < element.dim(); ++a) {
      element.force[j * element.dim() + a] = f[a];
      expected[a] += integrals_of_N[j] * f[a];
    }
  }
  return expected;
}

double norm(const Vector& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }

/// integral(N_j) / v0 of each node on an affine element: corners then mid-edge nodes.
std::vector<double> shape_integral_fractions(const std::string& type) {
  const std::map<std::string, std::pair<double, double>> fractions{
      {"tet4", {0.25, 0}},     {"hex8", {0.125, 0}},     {"tri3", {1.0 / 3, 0}},         {"quad4", {0.25, 0}},
      {"tet10", {-0.05, 0.2}}, {"tri6", {0.0, 1.0 / 3}}, {"quad8", {-1.0 / 12, 1.0 / 3}}};
  const tm_element_info& info = *registry().element(type);
  const int corners = info.order == 1 ? info.nodes : info.nodes - info.edge_count;
  std::vector<double> result(info.nodes, fractions.at(type).first);
  for (int j = corners; j < info.nodes; ++j) result[j] = fractions.at(type).second;
  return result;
}

TEST(CriteriaStress, VariedForcesMatchTheIntegralsOfTheShapeFunctions) {
  const Matrix A{{{1.2, 0.3, -0.1}, {0.1, 0.8, 0.2}, {0.0, -0.2, 1.1}}};
  for (const std::string type : {"tet4", "hex8", "tri3", "quad4", "tet10", "tri6", "quad8"}) {
    const tm_element_info& info = *registry().element(type);
    TestElement element = make_element(type, mapped_reference_nodes(info, A));
    const Vector expected = varied_forces(element, shape_integral_fractions(type));  // s at rest
    EXPECT_NEAR(element.value("R_S"), norm(expected), kTight * norm(expected)) << type;
    deform_affine(element, rotation(0.7));  // rotations keep v
    EXPECT_NEAR(element.value("R_S"), norm(expected), kTight * norm(expected)) << type;
  }
}

TEST(CriteriaStress, AnElementsOwnInternalForceAveragesToZeroOnALinearTet) {
  // The forces of one element sum to zero and a tet4 weighs its nodes
  // equally, so R_S needs the nodes' total (assembled) forces to say anything.
  const tm_kernel& kernel = registry().get("stvk", "tet4", "whole");
  TestElement tet = make_element(kernel, regular_tet());
  deform_affine(tet, stretch_x(1.3));
  kernel.gradient(tet.u.data(), tet.consts.data(), tet.force.data());
  EXPECT_GT(norm({tet.force[0], tet.force[1], tet.force[2]}), 1.0e4);
  EXPECT_NEAR(tet.value("R_S"), 0.0, 1e-9);
}

// --- Every element type and kernel ---------------------------------------------------------

class CriteriaOnKernel : public ::testing::TestWithParam<const tm_kernel*> {};

std::string kernel_label(const ::testing::TestParamInfo<const tm_kernel*>& info) {
  return std::string(info.param->law) + "_" + info.param->element + "_" + info.param->split;
}

/// A distorted but valid rest shape of the element.
Matrix rest_map(int dim) {
  if (dim == 2) return {{{1.3, 0.2, 0}, {-0.1, 0.7, 0}, {0, 0, 1}}};
  return {{{1.3, 0.2, -0.1}, {-0.1, 0.7, 0.15}, {0.05, 0.1, 1.6}}};
}

/// A general affine deformation with det > 0.
Matrix deformation_map(int dim) {
  if (dim == 2) return {{{1.1, 0.25, 0}, {-0.15, 0.85, 0}, {0, 0, 1}}};
  return {{{1.1, 0.25, -0.1}, {0.05, 0.9, 0.15}, {-0.1, 0.1, 1.25}}};
}

TEST_P(CriteriaOnKernel, AgreeWithTheReferenceElementAtRest) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = *registry().element(kernel.element);
  ASSERT_EQ(info.quadrature_points, kernel.quadrature_points);  // R_S pairs consts with shape_values
  ASSERT_EQ(info.nodes, kernel.nodes);
  const TestElement element = make_element(kernel, reference_nodes(info));
  EXPECT_EQ(element.value("R_EL"), 0.0);
  EXPECT_NEAR(element.value("R_V"), 0.0, kTight);
  EXPECT_EQ(element.value("R_NL"), 0.0);
  EXPECT_EQ(element.value("R_E"), 0.0);
  EXPECT_EQ(element.value("R_S"), 0.0);
  EXPECT_EQ(element.value("R_P"), 0.0);
  const double volume = reference_volume(info.name), mean = mean_edge(element, false);
  EXPECT_NEAR(element.value("R_VL"), volume / std::pow(mean, info.dim), kTight);
  EXPECT_GT(element.value("R_VLX"), 0.0);
}

TEST_P(CriteriaOnKernel, ExactUnderAGeneralAffineDeformation) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = *registry().element(kernel.element);
  const int dim = info.dim;
  TestElement element = make_element(kernel, mapped_reference_nodes(info, rest_map(dim)));
  const Matrix A = deformation_map(dim);
  deform_affine(element, A);
  const double J = determinant(A, dim);
  EXPECT_NEAR(element.value("R_V"), std::fabs(J - 1), kTight);
  EXPECT_NEAR(element.value("R_EL"), max_edge_strain(element), kTight);
  EXPECT_NEAR(element.value("R_NL"), quadratic_strain_norm(A, dim), kTight);
  EXPECT_NEAR(element.value("R_E"), green_strain_norm(A, dim), kTight);
  // R_P of the default ladder [hooke, stvk] reads the cell's constants as
  // theirs: a cell of a law with other constants is off that ladder and reads 0.
  const bool on_the_ladder = tensormass::parameter_names(kernel) == std::vector<std::string>{"young", "poisson"};
  const double stvk_error = on_the_ladder ? stress_error(stvk_stress(A, dim), hooke_stress(A, dim), dim) : 0.0;
  EXPECT_NEAR(element.value("R_P"), stvk_error, kTight * stvk_error) << "the default ladder [hooke, stvk]";
  const double deformed_volume = J * determinant(rest_map(dim), dim) * reference_volume(info.name);
  EXPECT_NEAR(element.value("R_VL"), deformed_volume / std::pow(mean_edge(element, true), dim), kTight);
  set_all_forces(element, {0.6, -0.8, 0.0});
  EXPECT_NEAR(element.value("R_S"), 1.0 / J, kTight);
}

TEST_P(CriteriaOnKernel, SimilarityKeepsQualityAndScalesTheRest) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = *registry().element(kernel.element);
  const int dim = info.dim;
  TestElement element = make_element(kernel, mapped_reference_nodes(info, rest_map(dim)));
  const double vl = element.value("R_VL"), vlx = element.value("R_VLX");
  const double s = 1.25, theta = 2.0;
  deform_affine(element, scaled(dim == 2 ? rotation(theta) : rotation(theta, {0.3, 1.0, -0.4}), s));
  EXPECT_NEAR(element.value("R_VL"), vl, kTight);
  EXPECT_NEAR(element.value("R_VLX"), vlx, kTight);
  EXPECT_NEAR(element.value("R_EL"), s - 1, kTight);
  EXPECT_NEAR(element.value("R_V"), std::pow(s, dim) - 1, kTight);
  EXPECT_NEAR(element.value("R_E"), std::sqrt(dim) * (s * s - 1) / 2, kTight) << "the rotation drops out";
}

TEST_P(CriteriaOnKernel, UniformStretchAlongX) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = *registry().element(kernel.element);
  TestElement element = make_element(kernel, mapped_reference_nodes(info, rest_map(info.dim)));
  const double s = 1.4;
  deform_affine(element, stretch_x(s));
  EXPECT_NEAR(element.value("R_V"), s - 1, kTight);
  EXPECT_NEAR(element.value("R_NL"), (s - 1) * (s - 1) / 2, kTight);
  EXPECT_NEAR(element.value("R_EL"), max_edge_strain(element), kTight);
  EXPECT_LE(element.value("R_EL"), s - 1 + kTight);
}

TEST_P(CriteriaOnKernel, EvaluateAllocatesNothing) {
  const tm_kernel& kernel = *GetParam();
  const tm_element_info& info = *registry().element(kernel.element);
  TestElement element = make_element(kernel, mapped_reference_nodes(info, rest_map(info.dim)));
  deform_affine(element, deformation_map(info.dim));
  set_all_forces(element, {1.0, 2.0, 3.0});
  std::vector<std::unique_ptr<Criterion>> criteria;
  for (const std::string& name : criterion_names()) criteria.push_back(make_criterion(name));
  const ElementView view = element.view();
  double sum = 0.0;
  const long before = test_support::allocation_count.load();
  for (const auto& criterion : criteria) sum += criterion->evaluate(view);
  EXPECT_EQ(test_support::allocation_count.load(), before);
  EXPECT_TRUE(std::isfinite(sum));
}

INSTANTIATE_TEST_SUITE_P(Registry, CriteriaOnKernel,
                         ::testing::ValuesIn(registry().kernels().begin(), registry().kernels().end()), kernel_label);

// --- R_P: the stress the first rung gets wrong ------------------------------------------------------

double stress_error_value(const TestElement& element, const std::string& target) {
  return make_criterion("R_P", {"hooke", target})->evaluate(element.view());
}

TEST(CriteriaStressError, NeoHookeanLadderMatchesTheClosedFormOnEveryElement) {
  for (const tm_element_info* info : registry().elements()) {
    const int dim = info->dim;
    TestElement element =
        make_element(registry().get("hooke", info->name, "whole"), mapped_reference_nodes(*info, rest_map(dim)));
    const Matrix A = deformation_map(dim);
    deform_affine(element, A);
    const double expected = stress_error(neohookean_stress(A, dim), hooke_stress(A, dim), dim);
    EXPECT_NEAR(stress_error_value(element, "neohookean"), expected, 1e-12 * expected) << info->name;
    EXPECT_GT(expected, 0.01) << "a deformation large enough to tell the laws apart";
  }
}

/// The constants are shared along the ladder: a cell already under the rich
/// law (its kernel swapped) reads the same value.
TEST(CriteriaStressError, SameValueWhicheverLadderLawTheCellIsUnder) {
  for (const std::string law : {"hooke", "stvk", "neohookean"}) {
    TestElement element = make_element(registry().get(law, "tet4", "whole"), regular_tet());
    deform_affine(element, deformation_map(3));
    const double expected =
        stress_error(neohookean_stress(deformation_map(3), 3), hooke_stress(deformation_map(3), 3), 3);
    EXPECT_NEAR(stress_error_value(element, "neohookean"), expected, 1e-12 * expected) << law;
  }
}

/// A rotation without strain: the rich laws give no stress, Hooke gives
/// sigma(sym(R) - I), all of it error.
TEST(CriteriaStressError, RigidRotationIsAllHookesError) {
  const double theta = 0.7;
  for (const std::string type : {"tri3", "quad4", "tet4", "hex8"}) {
    TestElement element = make_element(type, type == "tet4" ? regular_tet() : box(type));
    const int dim = element.dim();
    const Matrix R = dim == 2 ? rotation(theta) : rotation(theta, {1.0, -2.0, 0.5});
    deform_affine(element, R);
    const double expected = stress_error(Matrix{}, hooke_stress(R, dim), dim);
    for (const std::string target : {"stvk", "neohookean"})
      EXPECT_NEAR(stress_error_value(element, target), expected, 1e-9 * expected) << type << " " << target;
  }
}

/// Small strains: every rich law agrees with Hooke to first order, so R_P
/// shrinks with the square of the strain (R_NL alike), unlike the strain.
TEST(CriteriaStressError, ShrinksWithTheSquareOfASmallStrain) {
  TestElement element = make_element("tet4", regular_tet());
  deform_affine(element, stretch_x(1.0 + 1e-2));
  const double larger = stress_error_value(element, "neohookean");
  deform_affine(element, stretch_x(1.0 + 1e-3));
  const double smaller = stress_error_value(element, "neohookean");
  EXPECT_NEAR(larger / smaller, 100.0, 5.0);
}

TEST(CriteriaStressError, InvertedCellUnderNeoHookeanIsInfinite) {
  TestElement element = make_element("tet4", regular_tet());
  deform_affine(element, diagonal(1.0, 1.0, -0.5));
  EXPECT_EQ(stress_error_value(element, "neohookean"), std::numeric_limits<double>::infinity());
}

TEST(CriteriaStressError, LawsWithoutStressKernelsAreRefusedByName) {
  try {
    make_criterion("R_P", {"hooke", "no_such_law"});
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("no_such_law"), std::string::npos) << error.what();
  }
}

// --- Cost ------------------------------------------------------------------------------------------

/// A block of `count` copies of a distorted element (default split of Hooke)
/// with small random displacements and forces, laid out like a model.
struct ElementBlock {
  const tm_kernel* kernel;
  const tm_element_info* info;
  int count;
  std::vector<double> rest, consts, u, force;

  ElementView view(int e) const {
    const std::size_t nd = static_cast<std::size_t>(kernel->nodes) * kernel->dim;
    return {*info,
            *kernel,
            consts.data() + e * static_cast<std::size_t>(kernel->consts),
            rest.data() + e * nd,
            u.data() + e * nd,
            force.data() + e * nd,
            kernel->dim,
            kYoung};
  }
};

ElementBlock make_block(const std::string& type, int count) {
  const tm_element_info& info = *registry().element(type);
  const tm_kernel& kernel = registry().get("hooke", type, default_split("hooke", info));
  const TestElement one = make_element(kernel, mapped_reference_nodes(info, rest_map(info.dim)));
  ElementBlock block{&kernel, &info, count, {}, {}, {}, {}};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> small(-0.01, 0.01);
  for (int e = 0; e < count; ++e) {
    block.rest.insert(block.rest.end(), one.rest.begin(), one.rest.end());
    block.consts.insert(block.consts.end(), one.consts.begin(), one.consts.end());
    for (std::size_t i = 0; i < one.rest.size(); ++i) {
      block.u.push_back(small(random));
      block.force.push_back(small(random));
    }
  }
  return block;
}

/// Nanoseconds per element of `criterion`: the best of `batches` timings of
/// `sweeps` sweeps over the block (the best resists a busy machine).
double nanoseconds_per_element(const Criterion& criterion, const ElementBlock& block, int sweeps, int batches) {
  double checksum = 0.0, best = std::numeric_limits<double>::infinity();
  for (int b = 0; b < batches; ++b) {
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < sweeps; ++r)
      for (int e = 0; e < block.count; ++e) checksum += criterion.evaluate(block.view(e));
    const auto stop = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(stop - start).count());
  }
  EXPECT_TRUE(std::isfinite(checksum));
  return best / (double(sweeps) * block.count);
}

/// Nanoseconds per element of the kernel's gradient on the block, the best of `batches`.
double gradient_nanoseconds_per_element(const ElementBlock& block, int sweeps, int batches) {
  const std::size_t nd = static_cast<std::size_t>(block.kernel->nodes) * block.kernel->dim;
  std::vector<double> gradient(nd);
  double checksum = 0.0, best = std::numeric_limits<double>::infinity();
  for (int b = 0; b < batches; ++b) {
    const auto start = std::chrono::steady_clock::now();
    for (int r = 0; r < sweeps; ++r)
      for (int e = 0; e < block.count; ++e) {
        const ElementView view = block.view(e);
        block.kernel->gradient(view.u, view.consts, gradient.data());
        checksum += gradient[0];
      }
    const auto stop = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(stop - start).count());
  }
  EXPECT_TRUE(std::isfinite(checksum));
  return best / (double(sweeps) * block.count);
}

/// Prints (and records) ns per element of every criterion on `count`
/// elements of each type: 500 stay in cache, 20000 stream from memory.
void measure_cost(int count, int sweeps) {
  for (const std::string type : {"tet4", "quad4", "hex8", "tri3"}) {
    const ElementBlock block = make_block(type, count);
    std::string line = type + " (" + block.kernel->split + ", " + std::to_string(count) + " elements):";
    for (const std::string& name : criterion_names()) {
      const auto criterion = make_criterion(name);
      const double ns = nanoseconds_per_element(*criterion, block, sweeps, 7);
      char text[64];
      std::snprintf(text, sizeof text, "  %s %.1f ns", name.c_str(), ns);
      line += text;
      ::testing::Test::RecordProperty(type + "_" + name + "_" + std::to_string(count) + "_ns", std::to_string(ns));
#ifndef __SANITIZE_ADDRESS__  // sanitized code runs several times slower: the guard is for optimised builds
      EXPECT_LT(ns, 5000.0) << type << " " << name;  // only a gross regression guard
#endif
    }
    std::printf("%s  | hooke gradient %.1f ns\n", line.c_str(), gradient_nanoseconds_per_element(block, sweeps, 7));
  }
}

TEST(CriteriaCost, NanosecondsPerElementInCache) { measure_cost(500, 40); }

TEST(CriteriaCost, NanosecondsPerElementFromMemory) { measure_cost(20000, 1); }

}  // namespace
}  // namespace tensormass
