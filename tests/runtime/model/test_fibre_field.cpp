// Fibre fields (fibre_field.cpp): constant, formula and sampled directions,
// the nearest-sample lookup against a brute-force search, file errors; and
// a fibre law in the model: a unit hex8 under a uniaxial dead load with its
// fibres along, across and at 45 degrees to the load deforms as the closed
// form (transversely isotropic Mooney-Rivlin, solved here independently).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include "support/integrate.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/model/fibre_field.hpp"
#include "tensormass/model/material_laws.hpp"

namespace tensormass {
namespace {

using Vector = FibreField::Vector;
using test_support::TempDir;

std::string input_error(const std::function<void()>& action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(FibreField, ConstantAndFormulaFields) {
  const FibreField constant = FibreField::constant({0, 2, 0}, "m");
  EXPECT_TRUE(constant.given());
  EXPECT_EQ(constant.at({5, 6, 7}, "cell 0"), (Vector{0, 2, 0}));
  const FibreField circumferential = FibreField::formula({"-y", "x", "0"}, "m");
  EXPECT_EQ(circumferential.at({1, 2, 3}, "cell 0"), (Vector{-2, 1, 0}));
  EXPECT_FALSE(FibreField().given());
}

TEST(FibreField, ZeroDirectionsNameTheCellAndPoint) {
  EXPECT_NE(input_error([] {
              FibreField::constant({0, 0, 0}, "scene.yaml:3: materials[0].fibres");
            }).find("scene.yaml:3: materials[0].fibres: the fibre direction must be a non-zero vector"),
            std::string::npos);
  const FibreField field = FibreField::formula({"x", "y", "0"}, "scene.yaml:3: materials[0].fibres");
  const std::string message = input_error([&] { field.at({0, 0, 0}, "element 4 (hex8)"); });
  EXPECT_NE(message.find("element 4 (hex8) (centre (0, 0, 0)) is (0, 0, 0)"), std::string::npos) << message;
  EXPECT_NE(message.find("scene.yaml:3: materials[0].fibres"), std::string::npos) << message;
}

TEST(FibreField, SamplesGiveTheNearestSamplesDirection) {
  TempDir dir;
  std::mt19937_64 draw(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<std::array<double, 6>> samples(300);
  std::ofstream file(dir.file("fibres.csv"));
  file << "x,y,z,ax,ay,az\n# a comment\n";
  for (auto& s : samples) {
    for (double& v : s) v = unit(draw);
    file << s[0] << "," << s[1] << "," << s[2] << " " << s[3] << "\t" << s[4] << "," << s[5] << "\n";
  }
  file.close();
  const FibreField field = FibreField::samples(dir.file("fibres.csv"), "m");
  for (int trial = 0; trial < 200; ++trial) {
    const Vector x{1.5 * unit(draw), 1.5 * unit(draw), 1.5 * unit(draw)};
    std::size_t nearest = 0;
    double best = HUGE_VAL;
    for (std::size_t i = 0; i < samples.size(); ++i) {
      const double d =
          std::pow(samples[i][0] - x[0], 2) + std::pow(samples[i][1] - x[1], 2) + std::pow(samples[i][2] - x[2], 2);
      if (d < best) best = d, nearest = i;
    }
    const Vector a = field.at(x, "cell");
    // The file holds the numbers with 6 significant digits.
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(a[c], samples[nearest][3 + c], 1e-5) << "trial " << trial;
  }
}

TEST(FibreField, SampleFileErrorsNameTheFileAndLine) {
  TempDir dir;
  const auto error_of = [&](const std::string& text) {
    const std::string path = dir.file("f.csv");
    std::ofstream(path) << text;
    return input_error([&] { FibreField::samples(path, "m"); });
  };
  EXPECT_NE(error_of("0 0 0 1 0 0\n1 2 3\n").find("f.csv:2: expected 6 numbers"), std::string::npos);
  EXPECT_NE(error_of("0 0 0 1 0 0\n1 2 3 0 0 0\n").find("f.csv:2: the fibre direction must be a non-zero"),
            std::string::npos);
  EXPECT_NE(error_of("x y z ax ay az\n").find("no fibre samples"), std::string::npos);
  EXPECT_NE(error_of("0 0 nan 1 0 0\n").find("f.csv:1:"), std::string::npos);
  EXPECT_NE(input_error([&] { FibreField::samples(dir.file("missing.csv"), "m"); }).find("missing.csv"),
            std::string::npos);
}

// --- A fibre law in the model ----------------------------------------------------

using Matrix = std::array<std::array<double, 3>, 3>;

Matrix product(const Matrix& a, const Matrix& b) {
  Matrix c{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) c[i][j] += a[i][k] * b[k][j];
  return c;
}

Matrix transposed(const Matrix& a) {
  Matrix t{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) t[i][j] = a[j][i];
  return t;
}

double determinant(const Matrix& a) {
  return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
         a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
}

Matrix inverse(const Matrix& a) {
  const double det = determinant(a);
  Matrix b{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      b[i][j] = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / det;
    }
  return b;
}

struct TransverseMooneyRivlin {
  double c10, c01, eta, kappa;
  Vector a0;  // unit

  /// P = J sigma F^-T with sigma = 2/J [(W1 + I1 W2) Bbar - W2 Bbar^2 - (W1 I1 + 2 W2 I2)/3 I]
  /// + 2/J W4 (abar abar - I4/3 I) + kappa (J - 1) I (Holzapfel 6.6, 6.7).
  Matrix piola(const Matrix& F) const {
    const double J = determinant(F), s = std::pow(J, -2.0 / 3);
    Matrix B = product(F, transposed(F));
    for (auto& row : B)
      for (double& v : row) v *= s;
    const Matrix B2 = product(B, B);
    const double I1 = B[0][0] + B[1][1] + B[2][2];
    const double I2 = (I1 * I1 - (B2[0][0] + B2[1][1] + B2[2][2])) / 2;
    Vector a{};
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) a[i] += std::pow(J, -1.0 / 3) * F[i][k] * a0[k];
    const double I4 = a[0] * a[0] + a[1] * a[1] + a[2] * a[2], W4 = eta * (I4 - 1);
    Matrix sigma{};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        const double delta = i == j ? 1.0 : 0.0;
        sigma[i][j] = 2 / J * ((c10 + I1 * c01) * B[i][j] - c01 * B2[i][j] - (c10 * I1 + 2 * c01 * I2) / 3 * delta) +
                      2 / J * W4 * (a[i] * a[j] - I4 / 3 * delta) + kappa * (J - 1) * delta;
      }
    Matrix P = product(sigma, transposed(inverse(F)));
    for (auto& row : P)
      for (double& v : row) v *= J;
    return P;
  }
};

/// The upper-triangular F (F e_x stays along e_x, and F_zy = 0 fixes the
/// turn about x, as the test's supports do) with P = s e_x e_x: Gauss-Newton
/// on the 9 components of P - s e_x e_x over the 6 entries of F.
Matrix uniaxial_closed_form(const TransverseMooneyRivlin& law, double s) {
  const std::array<std::pair<int, int>, 6> entries = {{{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}}};
  Matrix F{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
  const auto residual = [&](const Matrix& G) {
    Matrix P = law.piola(G);
    P[0][0] -= s;
    return P;
  };
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Matrix r = residual(F);
    double jac[9][6];
    for (int k = 0; k < 6; ++k) {
      Matrix plus = F, minus = F;
      const double h = 1e-6;
      plus[entries[k].first][entries[k].second] += h;
      minus[entries[k].first][entries[k].second] -= h;
      const Matrix rp = residual(plus), rm = residual(minus);
      for (int m = 0; m < 9; ++m) jac[m][k] = (rp[m / 3][m % 3] - rm[m / 3][m % 3]) / (2 * h);
    }
    double normal[6][7] = {};  // J^T J | -J^T r
    for (int a = 0; a < 6; ++a) {
      for (int b = 0; b < 6; ++b)
        for (int m = 0; m < 9; ++m) normal[a][b] += jac[m][a] * jac[m][b];
      for (int m = 0; m < 9; ++m) normal[a][6] -= jac[m][a] * r[m / 3][m % 3];
    }
    for (int p = 0; p < 6; ++p)  // Gaussian elimination (J^T J is positive definite here)
      for (int q = p + 1; q < 6; ++q) {
        const double factor = normal[q][p] / normal[p][p];
        for (int c = p; c < 7; ++c) normal[q][c] -= factor * normal[p][c];
      }
    double step[6];
    for (int p = 5; p >= 0; --p) {
      double sum = normal[p][6];
      for (int c = p + 1; c < 6; ++c) sum -= normal[p][c] * step[c];
      step[p] = sum / normal[p][p];
    }
    for (int k = 0; k < 6; ++k) F[entries[k].first][entries[k].second] += step[k];
  }
  return F;
}

/// The unit hex8 under dead loads +-s along x on its x faces (s/4 per
/// node), held at three corners so that its F is upper triangular; returns F
/// from the displacements of the corners next to the origin.
Matrix uniaxial_hex8(const Vector& fibre, double s) {
  Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  const auto near = [](double a, double b) { return std::abs(a - b) < 1e-9; };
  mesh.add_node_group("origin", [&](double x, double y, double z) { return near(x, 0) && near(y, 0) && near(z, 0); });
  mesh.add_node_group("x_end", [&](double x, double y, double z) { return near(x, 1) && near(y, 0) && near(z, 0); });
  mesh.add_node_group("y_end", [&](double x, double y, double z) { return near(x, 0) && near(y, 1) && near(z, 0); });
  mesh.add_node_group("pulled", [&](double x, double, double) { return near(x, 1); });
  mesh.add_node_group("held", [&](double x, double, double) { return near(x, 0); });
  Scene scene = test::cantilever("transversely_isotropic_mooney_rivlin");
  MaterialSpec& material = scene.model.materials[0];
  material.constants = {{"c10", 1e3}, {"c01", 2e2}, {"eta", 5e3}, {"kappa", 1e5}};
  material.fibres[0] = FibreField::constant(fibre, "test material");
  scene.model.fixed = {"origin"};
  scene.model.loads.gravity = {0, 0, 0};
  PrescribedSpec x_end{.region = "x_end", .displacement = {}, .components = {false, true, true}};
  PrescribedSpec y_end{.region = "y_end", .displacement = {}, .components = {false, false, true}};
  scene.model.prescribed = {x_end, y_end};
  // Equal and opposite loads on both x faces: the supports take no force.
  scene.model.loads.nodal_forces = {{.region = "pulled", .force = {s / 4, 0, 0}},
                                    {.region = "held", .force = {-s / 4, 0, 0}}};
  scene.solver.load_steps = 4;
  SolveStatistics statistics;
  const State state = test::integrate(mesh, scene, statistics);
  Matrix F{};
  const std::array<const char*, 3> columns = {"x_end", "y_end", nullptr};
  for (int c = 0; c < 3; ++c) {
    int node = -1;
    if (columns[c]) {
      node = mesh.group(columns[c])->nodes.at(0);
    } else {
      for (int n = 0; n < mesh.node_count(); ++n)
        if (near(mesh.rest_positions[3 * n], 0) && near(mesh.rest_positions[3 * n + 1], 0) &&
            near(mesh.rest_positions[3 * n + 2], 1))
          node = n;
    }
    for (int r = 0; r < 3; ++r) F[r][c] = (r == c ? 1.0 : 0.0) + state.displacement[3 * node + r];
  }
  return F;
}

class FibreUniaxial : public testing::TestWithParam<std::pair<const char*, Vector>> {};

TEST_P(FibreUniaxial, DeformsAsTheClosedForm) {
  const Vector a0 = GetParam().second;
  const double norm = std::sqrt(a0[0] * a0[0] + a0[1] * a0[1] + a0[2] * a0[2]);
  const TransverseMooneyRivlin law{1e3, 2e2, 5e3, 1e5, {a0[0] / norm, a0[1] / norm, a0[2] / norm}};
  const double s = 800;  // Pa: about 10 % stretch across the fibres
  const Matrix expected = uniaxial_closed_form(law, s);
  const Matrix P = law.piola(expected);
  ASSERT_NEAR(P[0][0], s, 1e-9 * s);
  const Matrix actual = uniaxial_hex8(a0, s);  // the unnormalised direction: the kernel normalises it
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(actual[i][j], expected[i][j], 1e-7) << "F" << i << j;
}

INSTANTIATE_TEST_SUITE_P(Directions, FibreUniaxial,
                         testing::Values(std::pair<const char*, Vector>{"along", {2, 0, 0}},
                                         std::pair<const char*, Vector>{"across", {0, 1, 0}},
                                         std::pair<const char*, Vector>{"at_45", {1, 1, 0}}),
                         [](const auto& info) { return std::string(info.param.first); });

TEST(FibreUniaxial, FibresAlongTheLoadStiffenAndAt45DegreesShear) {
  const TransverseMooneyRivlin along{1e3, 2e2, 5e3, 1e5, {1, 0, 0}}, across{1e3, 2e2, 5e3, 1e5, {0, 1, 0}};
  const double r = std::sqrt(0.5);
  const TransverseMooneyRivlin oblique{1e3, 2e2, 5e3, 1e5, {r, r, 0}};
  EXPECT_LT(uniaxial_closed_form(along, 800)[0][0], uniaxial_closed_form(across, 800)[0][0] - 0.02);
  EXPECT_GT(std::abs(uniaxial_closed_form(oblique, 800)[0][1]), 0.01);  // shear couples at 45 degrees
  EXPECT_LT(std::abs(uniaxial_closed_form(along, 800)[0][1]), 1e-12);
}

TEST(FibreModel, ALawWithFibresNeedsAField) {
  Mesh mesh = test::beam(3, "hex8", {2, 1, 1});
  Scene scene = test::cantilever("transversely_isotropic_mooney_rivlin");
  scene.model.materials[0].constants = {{"c10", 1e3}, {"c01", 2e2}, {"eta", 5e3}, {"kappa", 1e5}};
  const std::string message = input_error([&] { const Model model(mesh, scene.model); });
  EXPECT_NE(message.find("reads a fibre direction; give the material `fibres`"), std::string::npos) << message;
}

}  // namespace
}  // namespace tensormass

namespace tensormass {
namespace {

/// Fibre directions differ cell by cell, so a fibre law shares its leading
/// constants with no other law: an adaptivity ladder holding one is
/// refused (check_ladder) rather than switching cells onto wrong directions.
TEST(FibreModel, AFibreLawSharesItsConstantsWithNoOtherLaw) {
  MaterialSpec material;
  material.law = "transversely_isotropic_mooney_rivlin";
  material.constants = {{"c10", 1e3}, {"c01", 2e2}, {"eta", 5e3}, {"kappa", 1e5}};
  material.fibres[0] = FibreField::constant({1, 0, 0}, "m");
  material.density = 1000;
  const MaterialLaws laws(material, "m");
  EXPECT_FALSE(laws.share_constants("transversely_isotropic_mooney_rivlin", "mooney_rivlin"));
  material.law = "mooney_rivlin";
  material.constants.erase("eta");
  EXPECT_TRUE(MaterialLaws(material, "m").share_constants("mooney_rivlin", "mooney_rivlin"));
}

}  // namespace
}  // namespace tensormass
