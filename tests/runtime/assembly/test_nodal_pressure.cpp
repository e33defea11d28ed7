// The averaged nodal pressure (the anp split, nodal_pressure.hpp) through the
// assembler: its forces are the derivative of its energy and its tangent the
// derivative of its forces (finite differences over every free dof, the
// patches' two-ring coupling included); a homogeneous deformation gives the
// whole kernels' forces and energy (every J_e and J_A equal); a bending
// cantilever near incompressibility locks under `whole` and not under `anp`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "support/assembly_checks.hpp"
#include "support/cantilever.hpp"
#include "tensormass/assembly/assembler.hpp"
#include "tensormass/assembly/nodal_pressure.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

using test::wavy_displacement;

Scene anp_cantilever(const std::string& law, double poisson, const std::string& split = "anp") {
  Scene scene = test::cantilever(law);
  if (law == "mooney_rivlin") scene.model.materials[0].constants = {{"c10", 2e5}, {"c01", 5e4}, {"kappa", 5e7}};
  else scene.model.materials[0].constants = elastic_constants(1e6, poisson);
  scene.model.materials[0].split = split;
  return scene;
}

struct Case {
  std::string law;
  int dim;
  std::string cut = "tet6";  ///< the 3D beam's cells: tet6 (tet4) or prism6 (the fbar-based anp)
};

class NodalPressureDerivatives : public testing::TestWithParam<Case> {
 protected:
  Mesh mesh() const {
    return GetParam().dim == 3 ? test::beam(3, GetParam().cut, {3, 1, 1}) : test::beam(2, "tri3", {4, 2, 1});
  }
};

TEST_P(NodalPressureDerivatives, CellsAreAnpAndHavePatches) {
  const Mesh m = mesh();
  const Model model(m, anp_cantilever(GetParam().law, 0.45).model);
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_TRUE(nodal_pressure_split(model.kernel(cell)));
  const NodalPressure nodal(model);
  EXPECT_EQ(nodal.patch_count(), m.node_count());  // one material: one patch per node
}

TEST_P(NodalPressureDerivatives, TangentIsTheDerivativeOfTheForces) {
  const Mesh m = mesh();
  const Model model(m, anp_cantilever(GetParam().law, 0.45).model);
  const Assembler assembler(model);
  EXPECT_LT(test::tangent_error(model, assembler, wavy_displacement(model.dof_count(), 0.02)), 1e-6);
}

TEST_P(NodalPressureDerivatives, ForcesAreTheDerivativeOfTheEnergy) {
  const Mesh m = mesh();
  const Model model(m, anp_cantilever(GetParam().law, 0.45).model);
  const Assembler assembler(model);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.02);
  std::vector<double> g(model.dof_count());
  assembler.assemble(u, g, nullptr);
  const double h = 1e-6;
  double worst = 0, scale = 0;
  for (int dof : model.free_dofs()) {
    std::vector<double> up = u, um = u;
    up[dof] += h;
    um[dof] -= h;
    const double fd = (assembler.energy(up) - assembler.energy(um)) / (2 * h);
    worst = std::max(worst, std::abs(fd - g[dof]));
    scale = std::max(scale, std::abs(g[dof]));
  }
  EXPECT_LT(worst, 1e-5 * scale);
}

/// u = (F - I) X: every cell and every patch has the same J, so the bulk
/// part taken off the cells is the one put back at the nodes.
TEST_P(NodalPressureDerivatives, HomogeneousDeformationGivesTheWholeKernels) {
  const Mesh m = mesh();
  const Model anp(m, anp_cantilever(GetParam().law, 0.45).model);
  const Model whole(m, anp_cantilever(GetParam().law, 0.45, "whole").model);
  const double F[9] = {1.04, 0.02, -0.01, 0.03, 0.97, 0.02, -0.02, 0.01, 1.05};
  const int d = m.dim;
  std::vector<double> u(anp.dof_count());
  for (int node = 0; node < m.node_count(); ++node)
    for (int i = 0; i < d; ++i)
      for (int c = 0; c < d; ++c) u[node * d + i] += (F[i * 3 + c] - (i == c)) * m.rest_positions[node * 3 + c];
  const Assembler a(anp, false), b(whole, false);
  std::vector<double> ga(u.size()), gb(u.size());
  a.assemble(u, ga, nullptr);
  b.assemble(u, gb, nullptr);
  double worst = 0, scale = 0;
  for (std::size_t i = 0; i < u.size(); ++i) worst = std::max(worst, std::abs(ga[i] - gb[i]));
  for (double value : gb) scale = std::max(scale, std::abs(value));
  EXPECT_LT(worst, 1e-10 * scale);
  EXPECT_NEAR(a.energy(u), b.energy(u), 1e-11 * std::abs(b.energy(u)));
  // Not a comparison of a formulation with itself: a wavy u tells them apart.
  const std::vector<double> wavy = wavy_displacement(anp.dof_count(), 0.02);
  EXPECT_GT(std::abs(a.energy(wavy) - b.energy(wavy)), 1e-3 * std::abs(b.energy(wavy)));
}

INSTANTIATE_TEST_SUITE_P(Laws, NodalPressureDerivatives,
                         testing::Values(Case{"neohookean", 3}, Case{"hooke", 3}, Case{"mooney_rivlin", 3},
                                         Case{"stable_neohookean", 3}, Case{"neohookean", 2}, Case{"hooke", 2},
                                         Case{"neohookean", 3, "prism6"}, Case{"hooke", 3, "prism6"},
                                         Case{"mooney_rivlin", 3, "prism6"}),
                         [](const testing::TestParamInfo<Case>& info) {
                           return info.param.law + "_" + std::to_string(info.param.dim) + "d" +
                                  (info.param.cut == "tet6" ? "" : "_" + info.param.cut);
                         });

/// Cells blending between two laws (the adaptive model's smooth switch)
/// blend their bulk parts too: the tangent stays the forces' derivative.
TEST(NodalPressure, BlendingCellsBlendTheirBulkParts) {
  const Mesh mesh = test::beam(3, "tet6", {3, 1, 1});
  Model model(mesh, anp_cantilever("neohookean", 0.45).model);
  const tm_kernel& neohookean = model.kernel(0);
  for (int cell = 0; cell < model.cell_count(); cell += 2) {
    model.set_law(cell, "stable_neohookean");
    model.start_blend(cell, &neohookean);
    model.set_blend_weight(cell, 0.4);
  }
  const Assembler assembler(model);
  const std::vector<double> u = wavy_displacement(model.dof_count(), 0.02);
  EXPECT_LT(test::tangent_error(model, assembler, u), 1e-6);
  std::vector<double> g(model.dof_count());
  assembler.assemble(u, g, nullptr);
  double work = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) work += g[i] * u[i];
  EXPECT_TRUE(std::isfinite(work) && work > 0.0);
}

}  // namespace
}  // namespace tensormass
