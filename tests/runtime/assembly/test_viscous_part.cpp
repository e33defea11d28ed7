// The viscous part of viscoelastic laws: its force and tangent are the
// derivatives of the step's energy; a held stretch relaxes as the Prony
// series' relaxation function and a dead load creeps as its creep
// compliance (closed forms, computed here); a static solve gives the
// long-term response.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "support/integrate.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/viscous_part.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass {
namespace {

constexpr double kMu = 1e3, kKappa = 5e3;  // Pa: instantaneous shear and bulk moduli

/// k1, k2: the terms' weights on the bulk part's stress (0: it stays elastic).
Scene viscous_scene(double g1, double tau1, double g2, double tau2, SolverType type, double k1 = 0, double k2 = 0) {
  Scene scene = test::cantilever("viscoelastic_neohookean", type);
  scene.model.materials[0].constants = {{"mu", kMu}, {"kappa", kKappa}, {"g1", g1}, {"tau1", tau1},
                                        {"g2", g2},  {"tau2", tau2},    {"k1", k1}, {"k2", k2}};
  scene.model.materials[0].density = 1;
  scene.model.loads.gravity = {0, 0, 0};
  return scene;
}

bool near(double a, double b) { return std::abs(a - b) < 1e-9; }

// --- Derivatives -------------------------------------------------------------

struct Case {
  const char* name;
  int dim;
  const char* cut;  ///< the beam's cell type (test::beam)
  int order;
  const char* split;
  double bulk_weight;  ///< k1 (k2 = 0.1)
};

class ViscousDerivatives : public testing::TestWithParam<Case> {};

/// After two committed steps (a non-zero history), g = dE/du and K = dg/du
/// by central differences, E the assembler's energy of the step.
TEST_P(ViscousDerivatives, ForceAndTangentDeriveFromTheStepEnergy) {
  const Case c = GetParam();
  const Mesh mesh = test::beam(c.dim, c.cut, {2, 1, 1}, c.order);
  Scene scene = viscous_scene(0.4, 0.5, 0.3, 2.0, SolverType::implicit_euler, c.bulk_weight, 0.1);
  scene.model.materials[0].split = c.split;
  const Model model(mesh, scene.model);
  Assembler assembler(model);
  ASSERT_FALSE(assembler.viscous_part().empty());
  std::mt19937_64 draw(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const auto random_u = [&](double size) {
    std::vector<double> u(model.dof_count());
    for (double& x : u) x = size * unit(draw);
    return u;
  };
  std::vector<double> history;
  for (double size : {0.04, 0.08}) {
    assembler.begin_viscous_step(history, 0.3);
    assembler.commit_viscous_step(random_u(size), history);
  }
  assembler.begin_viscous_step(history, 0.3);
  const std::vector<double> u = random_u(0.06);
  std::vector<double> g(u.size());
  SparseMatrix K = assembler.pattern();
  assembler.assemble(u, g, &K);
  const double h = 1e-6;
  const auto& free = model.free_dofs();
  double scale = 0.0;
  for (int d : free) scale = std::max(scale, std::abs(g[d]));
  for (int d : free) {
    std::vector<double> plus = u, minus = u;
    plus[d] += h, minus[d] -= h;
    const double fd = (assembler.energy(plus) - assembler.energy(minus)) / (2 * h);
    EXPECT_NEAR(g[d], fd, 1e-6 * scale) << "dof " << d;
  }
  std::vector<double> direction(free.size()), Kd(free.size());
  for (double& x : direction) x = unit(draw);
  assembler.tangent_product(K, direction, Kd);
  std::vector<double> plus = u, minus = u, g_plus(u.size()), g_minus(u.size());
  for (std::size_t i = 0; i < free.size(); ++i) plus[free[i]] += h * direction[i], minus[free[i]] -= h * direction[i];
  assembler.assemble(plus, g_plus, nullptr);
  assembler.assemble(minus, g_minus, nullptr);
  double k_scale = 0.0;
  for (double x : Kd) k_scale = std::max(k_scale, std::abs(x));
  for (std::size_t i = 0; i < free.size(); ++i)
    EXPECT_NEAR(Kd[i], (g_plus[free[i]] - g_minus[free[i]]) / (2 * h), 1e-6 * k_scale) << "free dof " << i;
}

INSTANTIATE_TEST_SUITE_P(
    Elements, ViscousDerivatives,
    testing::Values(Case{"tet4", 3, "tet6", 1, "whole", 0.0}, Case{"hex8", 3, "hex8", 1, "whole", 0.3},
                    Case{"tet10", 3, "tet6", 2, "whole", 0.0}, Case{"tet4_anp", 3, "tet6", 1, "anp", 0.3},
                    Case{"tri3", 2, "tri3", 1, "whole", 0.3}, Case{"quad4", 2, "quad4", 1, "whole", 0.0},
                    Case{"tri3_anp", 2, "tri3", 1, "anp", 0.0}),
    [](const auto& info) { return std::string(info.param.name); });

// --- Relaxation --------------------------------------------------------------

using Matrix = std::array<std::array<double, 3>, 3>;

Matrix inverse(const Matrix& A) {
  const double det = A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1]) -
                     A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0]) +
                     A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
  Matrix inv{};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      const int i1 = (j + 1) % 3, i2 = (j + 2) % 3, j1 = (i + 1) % 3, j2 = (i + 2) % 3;
      inv[i][j] = (A[i1][j1] * A[i2][j2] - A[i1][j2] * A[i2][j1]) / det;
    }
  return inv;
}

/// P(t) = F (K(t) S_U + G(t) S_d) of the law at a held F, with
/// S_d = mu J^(-2/3) (I - I1/3 C^-1) and S_U = kappa J (J - 1) C^-1.
Matrix relaxed_piola(const Matrix& F, double relaxation, double bulk_relaxation) {
  Matrix C{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c) C[a][b] += F[c][a] * F[c][b];
  const Matrix Cinv = inverse(C);
  const double J =
      std::sqrt(C[0][0] * (C[1][1] * C[2][2] - C[1][2] * C[2][1]) - C[0][1] * (C[1][0] * C[2][2] - C[1][2] * C[2][0]) +
                C[0][2] * (C[1][0] * C[2][1] - C[1][1] * C[2][0]));
  const double I1 = C[0][0] + C[1][1] + C[2][2];
  Matrix S{}, P{};
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double Sd = kMu * std::pow(J, -2.0 / 3.0) * ((a == b ? 1.0 : 0.0) - I1 / 3 * Cinv[a][b]);
      S[a][b] = bulk_relaxation * kKappa * J * (J - 1) * Cinv[a][b] + relaxation * Sd;
    }
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c) P[a][b] += F[a][c] * S[c][b];
  return P;
}

/// A unit hex8 stretched in one very short step to a held F and left to
/// relax: the nominal stress on its x = 1 face (the sum of the face's nodal
/// forces) follows G(t) = g_inf + g1 exp(-t/tau1) + g2 exp(-t/tau2) in the
/// isochoric part and K(t) likewise with k1, k2 in the bulk part (k = 0:
/// the bulk part stays elastic).
class ViscousRelaxation : public testing::TestWithParam<std::array<double, 2>> {};

TEST_P(ViscousRelaxation, AHeldStretchRelaxesAsTheRelaxationFunctions) {
  const double g1 = 0.3, tau1 = 0.2, g2 = 0.5, tau2 = 2.0, k1 = GetParam()[0], k2 = GetParam()[1];
  const Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  Scene scene = viscous_scene(g1, tau1, g2, tau2, SolverType::implicit_euler, k1, k2);
  const Model model(mesh, scene.model);
  Assembler assembler(model);
  const Matrix F = {{{1.25, 0.1, 0.0}, {0.0, 0.9, 0.05}, {0.02, 0.0, 0.95}}};
  std::vector<double> u(model.dof_count());
  for (int n = 0; n < mesh.node_count(); ++n)
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) u[3 * n + a] += (F[a][b] - (a == b ? 1.0 : 0.0)) * mesh.rest_positions[3 * n + b];
  std::vector<double> history, g(u.size());
  double t = 0;
  const double first = 1e-7;  // the step in strain takes this long
  for (int step = 0; t < 6.0; ++step) {
    const double dt = step == 0 ? first : 0.05;
    assembler.begin_viscous_step(history, dt);
    assembler.assemble(u, g, nullptr);
    assembler.commit_viscous_step(u, history);
    t += dt;
    if (step % 10 != 0) continue;
    // The stretch ramps over the first step: as a step at its middle, to O(first^2).
    const double since = t - first / 2;
    const double relaxation = 1 - g1 - g2 + g1 * std::exp(-since / tau1) + g2 * std::exp(-since / tau2);
    const double bulk_relaxation = 1 - k1 - k2 + k1 * std::exp(-since / tau1) + k2 * std::exp(-since / tau2);
    const Matrix P = relaxed_piola(F, relaxation, bulk_relaxation);
    std::array<double, 3> face{};
    for (int n = 0; n < mesh.node_count(); ++n)
      if (near(mesh.rest_positions[3 * n], 1))
        for (int a = 0; a < 3; ++a) face[a] += g[3 * n + a];
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(face[a], P[a][0], 1e-8 * kMu) << "t = " << t << ", component " << a;
  }
}

INSTANTIATE_TEST_SUITE_P(BulkWeights, ViscousRelaxation,
                         testing::Values(std::array<double, 2>{0.0, 0.0}, std::array<double, 2>{0.4, 0.25}),
                         [](const auto& info) {
                           return std::string(info.param[0] > 0 ? "bulk_relaxes" : "bulk_elastic");
                         });

// --- Creep -------------------------------------------------------------------

/// Uniaxial creep strain under a small nominal stress s held from t = 0:
/// s (J_G(t)/3 + 1/(9 kappa)), the shear creep compliance of one Prony term
/// J_G(t) = (1/g_inf + (1 - 1/g_inf) exp(-g_inf t / tau)) / mu.
double creep_strain(double s, double g1, double tau, double t) {
  const double g_inf = 1 - g1;
  const double shear = (1 / g_inf + (1 - 1 / g_inf) * std::exp(-g_inf * t / tau)) / kMu;
  return s * (shear / 3 + 1 / (9 * kKappa));
}

/// The unit hex8 on three symmetry planes, pulled by s on its x = 1 face.
Scene creep_scene(double g1, double tau, SolverType type, double dt, int steps, Mesh& mesh, double s) {
  mesh.add_node_group("x0", [](double x, double, double) { return near(x, 0); });
  mesh.add_node_group("y0", [](double, double y, double) { return near(y, 0); });
  mesh.add_node_group("z0", [](double, double, double z) { return near(z, 0); });
  mesh.add_node_group("pulled", [](double x, double, double) { return near(x, 1); });
  Scene scene = viscous_scene(g1, tau, 0.0, 1.0, type);
  scene.model.fixed = {};
  scene.model.prescribed = {{.region = "x0", .displacement = {}, .components = {true, false, false}},
                            {.region = "y0", .displacement = {}, .components = {false, true, false}},
                            {.region = "z0", .displacement = {}, .components = {false, false, true}}};
  scene.model.loads.nodal_forces = {{.region = "pulled", .force = {s / 4, 0, 0}}};
  scene.solver.dt = dt;
  scene.solver.steps = steps;
  scene.solver.load_steps = 1;
  // Mass damping makes the run quasi-static: the oscillation of the unit
  // cube (about 0.04 s) dies out long before the creep (tau = 10 s) moves.
  scene.solver.damping_mass = 30;
  return scene;
}

class ViscousCreep : public testing::TestWithParam<SolverType> {};

TEST_P(ViscousCreep, ADeadLoadCreepsAsTheCreepCompliance) {
  const double g1 = 0.6, tau = 10.0, s = 0.1;
  const bool implicit = GetParam() == SolverType::implicit_euler;
  // The load's jump at t = 0 is integrated as a ramp over the first step:
  // an error of about g1 dt / (2 tau) that fades with the memory.
  const double dt = implicit ? 0.01 : 0.002;
  Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  const Scene scene = creep_scene(g1, tau, GetParam(), dt, static_cast<int>(std::lround(40.0 / dt)), mesh, s);
  const int corner = [&] {
    for (int n = 0; n < mesh.node_count(); ++n)
      if (near(mesh.rest_positions[3 * n], 1) && near(mesh.rest_positions[3 * n + 1], 0) &&
          near(mesh.rest_positions[3 * n + 2], 0))
        return n;
    return -1;
  }();
  int checked = 0;
  SolveStatistics statistics;
  test::integrate(mesh, scene, statistics, [&](const State& state) {
    const double t = state.time;
    if (t < 1.0 || std::abs(t / 5.0 - std::round(t / 5.0)) > 1e-9) return false;
    const double expected = creep_strain(s, g1, tau, t);
    EXPECT_NEAR(state.displacement[3 * corner], expected, 1e-3 * expected) << "t = " << t;
    ++checked;
    return false;
  });
  EXPECT_EQ(checked, 8);
  // The creep is visible: 2.5 times the instantaneous strain at the end.
  EXPECT_GT(creep_strain(s, g1, tau, 40.0), 2.0 * creep_strain(s, g1, tau, 0.0));
}

INSTANTIATE_TEST_SUITE_P(Integrators, ViscousCreep,
                         testing::Values(SolverType::implicit_euler, SolverType::explicit_euler), [](const auto& info) {
                           return std::string(info.param == SolverType::implicit_euler ? "implicit" : "explicit");
                         });

/// A static solve is the long-term equilibrium: shear modulus g_inf mu,
/// bulk modulus k_inf kappa.
TEST(ViscousStatic, AStaticSolveGivesTheLongTermResponse) {
  const double g1 = 0.6, k1 = 0.5, s = 0.1;
  Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  Scene scene = creep_scene(g1, 10.0, SolverType::static_newton, 0, 0, mesh, s);
  scene.model.materials[0].constants["k1"] = k1;
  SolveStatistics statistics;
  const State state = test::integrate(mesh, scene, statistics);
  const double expected = s * (1 / (3 * (1 - g1) * kMu) + 1 / (9 * (1 - k1) * kKappa));
  for (int n = 0; n < mesh.node_count(); ++n)
    if (near(mesh.rest_positions[3 * n], 1)) EXPECT_NEAR(state.displacement[3 * n], expected, 1e-3 * expected);
}

// --- Input -------------------------------------------------------------------

std::string input_error(const Model& model) {
  try {
    const ViscousPart part(model);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ViscousPartInput, WeightsSummingToOneOrMoreAreRefused) {
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  const Scene scene = viscous_scene(0.6, 1.0, 0.4, 2.0, SolverType::implicit_euler);
  const Model model(mesh, scene.model);
  const std::string message = input_error(model);
  EXPECT_NE(message.find("the Prony weights of law 'viscoelastic_neohookean' sum to 1.0"), std::string::npos)
      << message;
}

TEST(ViscousPartInput, SplitsOtherThanWholeAndOnePointAnpAreRefused) {
  const Mesh mesh = test::beam(3, "hex8", {2, 1, 1});
  Scene scene = viscous_scene(0.3, 1.0, 0.2, 2.0, SolverType::implicit_euler);
  scene.model.materials[0].split = "fbar";
  const Model model(mesh, scene.model);
  const std::string message = input_error(model);
  EXPECT_NE(message.find("hex8 cells run the fbar split; viscoelastic cells take the whole split"), std::string::npos)
      << message;
}

TEST(ViscousPartInput, ElasticModelsHaveNoViscousCells) {
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  const Model model(mesh, test::cantilever("neohookean").model);
  const ViscousPart part(model);
  EXPECT_TRUE(part.empty());
  EXPECT_EQ(part.history_size(), 0u);
  EXPECT_EQ(part.index_of(0), -1);
}

}  // namespace
}  // namespace tensormass
