// Model: lumped masses, consistent loads, constraints, rest Jacobians.
#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <numeric>
#include <stdexcept>

#include "support/cantilever.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

struct BeamCase {
  int dim;
  std::string cut;
  int order;
};

class ModelOnBeams : public ::testing::TestWithParam<BeamCase> {};

double component_sum(const std::vector<double>& values, int dim, int component) {
  double sum = 0;
  for (std::size_t i = component; i < values.size(); i += dim) sum += values[i];
  return sum;
}

TEST_P(ModelOnBeams, MassAndGravityIntegrateDensityTimesVolume) {
  const BeamCase c = GetParam();
  const Mesh mesh = test::beam(c.dim, c.cut, {4, 2, 2}, c.order);
  const Scene scene = test::cantilever("stvk");
  const Model model(mesh, scene.model);
  const double volume = c.dim == 2 ? 2.0 * 1.0 : 2.0 * 1.0 * 1.0;  // L = 4/2, H = 1, W = 2/2
  for (int a = 0; a < c.dim; ++a)
    EXPECT_NEAR(component_sum(model.lumped_mass(), c.dim, a), 1000 * volume, 1e-9 * 1000 * volume);
  for (double m : model.lumped_mass()) EXPECT_GT(m, 0.0);
  EXPECT_NEAR(component_sum(model.gravity_load(), c.dim, 1), -9.81 * 1000 * volume, 1e-9 * 9810 * volume);
  EXPECT_NEAR(component_sum(model.gravity_load(), c.dim, 0), 0.0, 1e-9);
}

TEST_P(ModelOnBeams, PressureOnTipPushesInwardWithTheFaceArea) {
  const BeamCase c = GetParam();
  const Mesh mesh = test::beam(c.dim, c.cut, {4, 2, 2}, c.order);
  Scene scene = test::cantilever("hooke");
  scene.model.loads.pressures = {{"tip", 250.0, 0}};
  const Model model(mesh, scene.model);
  const double area = 1.0;  // H (times W = 1 in 3D, unit thickness in 2D)
  EXPECT_NEAR(component_sum(model.surface_load(), c.dim, 0), -250.0 * area, 1e-9);
  EXPECT_NEAR(component_sum(model.surface_load(), c.dim, 1), 0.0, 1e-9);
}

TEST_P(ModelOnBeams, ClampedDofsAreNotFree) {
  const BeamCase c = GetParam();
  const Mesh mesh = test::beam(c.dim, c.cut, {4, 2, 2}, c.order);
  const Model model(mesh, test::cantilever("hooke").model);
  const Group& clamp = *mesh.group("clamp");
  EXPECT_EQ(model.free_dof_count(), model.dof_count() - c.dim * static_cast<int>(clamp.nodes.size()));
  for (int node : clamp.nodes) EXPECT_EQ(model.free_index()[node * c.dim], -1);
}

INSTANTIATE_TEST_SUITE_P(Beams, ModelOnBeams,
                         ::testing::Values(BeamCase{2, "quad4", 1}, BeamCase{2, "tri3", 1}, BeamCase{2, "quad4", 2},
                                           BeamCase{2, "tri3", 2}, BeamCase{3, "hex8", 1}, BeamCase{3, "tet5", 1},
                                           BeamCase{3, "tet6", 1}, BeamCase{3, "prism6", 1}, BeamCase{3, "pyramid5", 1},
                                           BeamCase{3, "hex8", 2}, BeamCase{3, "tet6", 2}),
                         [](const auto& info) {
                           return std::to_string(info.param.dim) + "d_" + info.param.cut + "_order" +
                                  std::to_string(info.param.order);
                         });

TEST(Model, InvertedElementAtRestIsNamed) {
  Mesh mesh = test::beam(3, "hex8", {3, 1, 1});
  std::swap(mesh.blocks[0].connectivity[0], mesh.blocks[0].connectivity[1]);
  std::swap(mesh.blocks[0].connectivity[2], mesh.blocks[0].connectivity[3]);
  std::swap(mesh.blocks[0].connectivity[4], mesh.blocks[0].connectivity[5]);
  std::swap(mesh.blocks[0].connectivity[6], mesh.blocks[0].connectivity[7]);
  try {
    Model model(mesh, test::cantilever("stvk").model);
    FAIL() << "an inverted element was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("element 0 (hex8"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("non-positive Jacobian"), std::string::npos) << error.what();
  }
}

/// A unit hexahedron whose corner 0 sits at (0.45, 0.45, 0.45): positive at
/// its Gauss points, folded at that corner (det = 1 - 3 * 0.45).
TEST(Model, ElementFoldedAtACornerAtRestIsNamed) {
  Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  const int corner = mesh.blocks[0].connectivity[0];
  for (int a = 0; a < 3; ++a) mesh.rest_positions[3 * corner + a] = 0.45;
  try {
    Model model(mesh, test::cantilever("stvk").model);
    FAIL() << "an element folded at a corner was accepted";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("element 0 (hex8"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("at corner 0"), std::string::npos) << error.what();
  }
}

/// The same fold reached by a displacement: the quadrature points alone
/// would not see it.
TEST(Model, InversionCheckSeesAFoldAtACorner) {
  const Mesh mesh = test::beam(3, "hex8", {1, 1, 1});
  const Model model(mesh, test::cantilever("neohookean").model);
  std::vector<double> u(model.dof_count(), 0.0);
  const int corner = mesh.blocks[0].connectivity[0];
  for (int a = 0; a < 3; ++a) u[3 * corner + a] = 0.45 - mesh.rest_positions[3 * corner + a];
  EXPECT_EQ(model.first_inverted_cell(u), 0);
  for (int a = 0; a < 3; ++a) u[3 * corner + a] = 0.3 - mesh.rest_positions[3 * corner + a];
  EXPECT_EQ(model.first_inverted_cell(u), -1);
}

TEST(Model, StaticSceneWithoutConstraintsIsRefusedByValidation) {
  const Mesh mesh = test::beam(2, "quad4", {4, 2, 1});
  Scene scene = test::cantilever("stvk");
  scene.model.fixed.clear();
  EXPECT_THROW(validate_against_mesh(scene, mesh), InputError);
}

TEST(Model, UnvalidatedSpecIsRefusedWithoutCrashing) {
  const Mesh mesh = test::beam(2, "quad4", {4, 2, 1});
  Scene unknown_group = test::cantilever("stvk");
  unknown_group.model.fixed = {"no_such_group"};
  EXPECT_THROW(Model(mesh, unknown_group.model), std::invalid_argument);
  Scene unknown_law = test::cantilever("no_such_law");
  EXPECT_THROW(Model(mesh, unknown_law.model), std::invalid_argument);
}

TEST(Model, DefaultSplitIsWholeAndAMaterialMayChooseAnother) {
  const Mesh mesh = test::beam(2, "quad4", {4, 2, 1});
  const Model hooke(mesh, test::cantilever("hooke").model);
  EXPECT_STREQ(hooke.kernel(0).split, "whole");
  Scene tensor = test::cantilever("hooke");
  tensor.model.materials[0].split = "tensor";
  EXPECT_STREQ(Model(mesh, tensor.model).kernel(0).split, "tensor");
}

TEST(Model, SwitchingFromTensorHookeToStvkMatchesAFreshStvkModel) {
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  Scene tensor_hooke = test::cantilever("hooke");
  tensor_hooke.model.materials[0].split = "tensor";
  Model switched(mesh, tensor_hooke.model);
  const Model reference(mesh, test::cantilever("stvk").model);
  std::vector<double> u(switched.dof_count());
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = 0.01 * std::sin(1.0 + i);
  for (int cell = 0; cell < switched.cell_count(); ++cell) switched.set_law(cell, "stvk");
  EXPECT_NEAR(switched.strain_energy(u), reference.strain_energy(u), 1e-12 * reference.strain_energy(u));
  EXPECT_EQ(switched.law_id(0), reference.law_id(0));
}

/// `split: fbar` binds the mean-dilatation kernels where the element has
/// them and `whole` elsewhere (a mixed mesh); a switch of law stays fbar.
TEST(Model, FbarCellsSwitchLawWithinFbarAndOtherElementsKeepWhole) {
  const Mesh mesh = test::beam(3, "hex8", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  scene.model.materials[0].split = "fbar";
  Model model(mesh, scene.model);
  EXPECT_STREQ(model.kernel(0).split, "fbar");
  model.set_law(0, "neohookean");
  EXPECT_STREQ(model.kernel(0).law, "neohookean");
  EXPECT_STREQ(model.kernel(0).split, "fbar");
  const Mesh tets = test::beam(3, "tet6", {2, 1, 1});
  EXPECT_STREQ(Model(tets, scene.model).kernel(0).split, "whole");
}

/// `split: anp` binds the nodal-pressure kernels on tet4 and the mean
/// dilatation on hex8 (a mixed mesh's two first-order families); a switch of
/// law stays anp.
TEST(Model, AnpCellsSwitchLawWithinAnpAndHexahedraTakeFbar) {
  const Mesh tets = test::beam(3, "tet6", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  scene.model.materials[0].split = "anp";
  Model model(tets, scene.model);
  EXPECT_STREQ(model.kernel(0).split, "anp");
  EXPECT_TRUE(nodal_pressure_split(model.kernel(0)));
  model.set_law(0, "neohookean");
  EXPECT_STREQ(model.kernel(0).law, "neohookean");
  EXPECT_STREQ(model.kernel(0).split, "anp");
  const Mesh hexes = test::beam(3, "hex8", {2, 1, 1});
  EXPECT_STREQ(Model(hexes, scene.model).kernel(0).split, "fbar");
}

/// Flipping every cell along x (u_x = -2 x, so F_xx = -1) inverts them all:
/// the check names one under neo-Hookean and none under the invertible
/// stable neo-Hookean, whose energy stays finite there.
TEST(Model, InversionCheckSkipsInvertibleLaws) {
  const Mesh mesh = test::beam(3, "tet6", {2, 1, 1});
  const Model neohookean(mesh, test::cantilever("neohookean").model);
  const Model stable(mesh, test::cantilever("stable_neohookean").model);
  std::vector<double> flipped(neohookean.dof_count(), 0.0);
  for (int node = 0; node < mesh.node_count(); ++node) flipped[3 * node] = -2.0 * mesh.rest_positions[3 * node];
  EXPECT_EQ(neohookean.first_inverted_cell(flipped), 0);
  EXPECT_EQ(stable.first_inverted_cell(flipped), -1);
  EXPECT_TRUE(std::isfinite(stable.strain_energy(flipped)));
  EXPECT_GT(stable.strain_energy(flipped), 0.0);
}

/// Above 4,096 cells the check runs on all threads: it still names the
/// smallest inverted cell, the one a single thread (scanning in order)
/// names. Only the beam's far end is flipped, so the answer is a cell there.
TEST(Model, InversionCheckNamesTheSmallestInvertedCellOnAnyThreadCount) {
  const Mesh mesh = test::beam(3, "tet6", {20, 6, 6});
  const Model model(mesh, test::cantilever("neohookean").model);
  ASSERT_GE(model.cell_count(), 4096);
  std::vector<double> u(model.dof_count(), 0.0);
  const double far = 0.8 * 20.0 / 6.0;  // the beam is 20/6 long
  for (int node = 0; node < mesh.node_count(); ++node)
    if (mesh.rest_positions[3 * node] > far) u[3 * node] = -3.0 * (mesh.rest_positions[3 * node] - far);
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  const int one = model.first_inverted_cell(u);
  omp_set_num_threads(2);
  const int two = model.first_inverted_cell(u);
  omp_set_num_threads(threads);
  EXPECT_GT(one, 0);
  EXPECT_EQ(one, two);
  bool touches_far_end = false;
  for (int node : model.cell_nodes(one)) touches_far_end |= mesh.rest_positions[3 * node] > far;
  EXPECT_TRUE(touches_far_end);
}

}  // namespace
}  // namespace tensormass
