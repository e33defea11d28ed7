// A model's loads and constraints (model_loads.cpp behind
// tensormass/model/model.hpp): nodal forces per node, pressure shared as the
// consistent load of linear and quadratic edges and pushing into the body
// from either side, the energy scale, prescribed rotations, a later
// constraint on a dof replacing an earlier one, and hold(). (Masses, gravity
// and pressure totals on every beam: test_model.cpp.)
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/cantilever.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/model/model.hpp"

namespace tensormass {
namespace {

/// The surface load on `node` along `axis`.
double load_at(const Model& model, int node, int axis) {
  return model.surface_load()[static_cast<std::size_t>(node * model.dim() + axis)];
}

/// The node of `mesh` at rest position (x, y, 0), or -1.
int node_at(const Mesh& mesh, double x, double y) {
  for (int n = 0; n < mesh.node_count(); ++n)
    if (std::abs(mesh.rest_positions[3 * n] - x) < 1e-12 && std::abs(mesh.rest_positions[3 * n + 1] - y) < 1e-12)
      return n;
  return -1;
}

/// The prescribed entry of `dof`, or nullptr.
const PrescribedDof* prescribed_dof(const Model& model, int dof) {
  for (const PrescribedDof& p : model.prescribed())
    if (p.dof == dof) return &p;
  return nullptr;
}

TEST(ModelLoads, ANodalForceActsOnEachNodeOfItsGroupAndForcesAdd) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});  // nodes at x = 0, 1, 2
  Scene scene = test::cantilever("hooke");
  scene.model.loads.nodal_forces = {{"tip", {1.5, -2.0, 0}, 0}, {"tip", {0.5, 0, 0}, 0}};
  const Model model(mesh, scene.model);
  for (int node = 0; node < mesh.node_count(); ++node) {
    const bool tip = std::abs(mesh.rest_positions[3 * node] - 2) < 1e-12;
    EXPECT_EQ(load_at(model, node, 0), tip ? 2.0 : 0.0) << node;
    EXPECT_EQ(load_at(model, node, 1), tip ? -2.0 : 0.0) << node;
  }
}

TEST(ModelLoads, PressureOnALinearEdgeIsSharedEquallyByItsEnds) {
  const Mesh mesh = test::beam(2, "quad4", {1, 1, 1});  // the unit square
  Scene scene = test::cantilever("hooke");
  scene.model.loads.pressures = {{"tip", 300.0, 0}};
  const Model model(mesh, scene.model);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 0), 0), -150.0, 1e-12);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 1), 0), -150.0, 1e-12);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 0), 1), 0.0, 1e-12);
}

TEST(ModelLoads, PressureOnAQuadraticEdgeGivesASixthToEachEndAndTwoThirdsToTheMiddle) {
  const Mesh mesh = test::beam(2, "quad4", {1, 1, 1}, 2);  // one quad8
  Scene scene = test::cantilever("hooke");
  scene.model.loads.pressures = {{"tip", 300.0, 0}};
  const Model model(mesh, scene.model);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 0), 0), -50.0, 1e-11);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 1), 0), -50.0, 1e-11);
  EXPECT_NEAR(load_at(model, node_at(mesh, 1, 0.5), 0), -200.0, 1e-11);
}

TEST(ModelLoads, PressurePushesIntoTheBodyOnEitherSide) {
  // The clamp at x = 0 faces -x: pushing into the body is +x there.
  for (const char* cut : {"hex8", "tet6"}) {
    const Mesh mesh = test::beam(3, cut, {2, 1, 1});  // [0,2] x [0,1] x [0,1]
    Scene scene = test::cantilever("hooke");
    scene.model.loads.pressures = {{"clamp", 40.0, 0}, {"tip", 10.0, 0}};
    const Model model(mesh, scene.model);
    double clamp_x = 0, tip_x = 0;
    for (int node = 0; node < mesh.node_count(); ++node) {
      const double x = mesh.rest_positions[3 * node];
      if (x < 1e-12) clamp_x += load_at(model, node, 0);
      else if (x > 2 - 1e-12) tip_x += load_at(model, node, 0);
      else EXPECT_EQ(load_at(model, node, 0), 0) << cut;
      EXPECT_NEAR(load_at(model, node, 1), 0, 1e-12) << cut;
      EXPECT_NEAR(load_at(model, node, 2), 0, 1e-12) << cut;
    }
    EXPECT_NEAR(clamp_x, 40.0, 1e-12) << cut;
    EXPECT_NEAR(tip_x, -10.0, 1e-12) << cut;
  }
}

TEST(ModelLoads, TheEnergyScaleIsYoungsModulusTimesTheRestVolume) {
  const Mesh mesh = test::beam(2, "tri3", {2, 1, 1});  // area 2, 4 triangles of 1/2
  const Model model(mesh, test::cantilever("hooke").model);
  EXPECT_NEAR(model.energy_scale(), 1e6 * 2.0, 1e-6);
  for (int cell = 0; cell < model.cell_count(); ++cell) EXPECT_NEAR(model.cell_energy_scale(cell), 1e6 * 0.5, 1e-7);
}

TEST(ModelLoads, CompletedPartialSumsReplaceMassGravityAndEnergyScale) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});
  Model model(mesh, test::cantilever("hooke").model);
  const std::vector<double> mass = model.lumped_mass(), gravity = model.gravity_load();
  int completed = 0;
  model.complete_partial_sums(
      [&](std::span<double> values) {
        ++completed;
        for (double& value : values) value *= 3;
      },
      42.0);
  EXPECT_EQ(completed, 2);
  for (std::size_t i = 0; i < mass.size(); ++i) {
    EXPECT_EQ(model.lumped_mass()[i], 3 * mass[i]);
    EXPECT_EQ(model.gravity_load()[i], 3 * gravity[i]);
  }
  EXPECT_EQ(model.energy_scale(), 42.0);
}

TEST(PrescribedRotation, TurnsAPointAboutItsAxisThroughItsCentre) {
  const PrescribedRotation about_z{{0, 0, 1}, {1, 0, 0}, std::numbers::pi / 2};
  const double x[3] = {2, 0, 5};
  auto u = about_z.displacement(x, 1.0);  // (2, 0) about (1, 0): to (1, 1)
  EXPECT_NEAR(u[0], -1, 1e-15);
  EXPECT_NEAR(u[1], 1, 1e-15);
  EXPECT_NEAR(u[2], 0, 1e-15);
  u = about_z.displacement(x, 0.5);  // 45 degrees
  EXPECT_NEAR(u[0], std::sqrt(0.5) - 1, 1e-15);
  EXPECT_NEAR(u[1], std::sqrt(0.5), 1e-15);
  EXPECT_EQ(about_z.displacement(x, 0.0), (std::array<double, 3>{0, 0, 0}));
  const PrescribedRotation about_x{{1, 0, 0}, {0, 0, 0}, std::numbers::pi / 2};
  const double y[3] = {3, 1, 0};
  u = about_x.displacement(y, 1.0);  // y turns into z, x stays
  EXPECT_NEAR(u[0], 0, 1e-15);
  EXPECT_NEAR(u[1], -1, 1e-15);
  EXPECT_NEAR(u[2], 1, 1e-15);
}

TEST(PrescribedRotation, TheModelTakesAUnitAxisAndRadiansAndConstrainsEveryComponent) {
  const Mesh mesh = test::beam(3, "hex8", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  PrescribedSpec turn;
  turn.region = "tip";
  turn.rotates = true;
  turn.rotation.axis = {2, 0, 0};
  turn.rotation.centre = {2, 0.5, 0.5};
  turn.rotation.angle = 30;
  turn.components = {false, false, false};  // a rotation holds every component anyway
  scene.model.prescribed = {turn};
  const Model model(mesh, scene.model);
  ASSERT_EQ(model.rotations().size(), 1u);
  EXPECT_EQ(model.rotations()[0].axis, (std::array<double, 3>{1, 0, 0}));
  EXPECT_NEAR(model.rotations()[0].radians, std::numbers::pi / 6, 1e-15);
  for (int node : mesh.group("tip")->nodes)
    for (int a = 0; a < 3; ++a) {
      const PrescribedDof* p = prescribed_dof(model, 3 * node + a);
      ASSERT_NE(p, nullptr);
      EXPECT_EQ(p->rotation, 0);
    }
}

TEST(PrescribedRotation, InTwoDimensionsAnAxisAlongMinusZTurnsTheOtherWay) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  PrescribedSpec turn;
  turn.region = "tip";
  turn.rotates = true;
  turn.rotation.angle = 90;
  turn.rotation.axis = {0, 0, -3};
  scene.model.prescribed = {turn};
  const Model minus(mesh, scene.model);
  EXPECT_NEAR(minus.rotations()[0].radians, -std::numbers::pi / 2, 1e-15);
  EXPECT_EQ(minus.rotations()[0].axis, (std::array<double, 3>{0, 0, 1}));
  scene.model.prescribed[0].rotation.axis = {1, 0, 0};  // 2D: the axis is z whatever is given
  const Model any(mesh, scene.model);
  EXPECT_NEAR(any.rotations()[0].radians, std::numbers::pi / 2, 1e-15);
  EXPECT_EQ(any.rotations()[0].axis, (std::array<double, 3>{0, 0, 1}));
}

TEST(PrescribedRotation, AZeroAxisIsRefused) {
  const Mesh mesh = test::beam(3, "hex8", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  PrescribedSpec turn;
  turn.region = "tip";
  turn.rotates = true;
  turn.rotation.axis = {0, 0, 0};
  scene.model.prescribed = {turn};
  try {
    const Model model(mesh, scene.model);
    ADD_FAILURE() << "a zero axis was accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "Model: a prescribed rotation with a zero axis");
  }
}

TEST(ModelConstraints, ALaterConstraintOnADofReplacesAnEarlierOne) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});
  Scene scene = test::cantilever("hooke");  // clamp fixed
  PrescribedSpec slide;
  slide.region = "clamp";
  slide.displacement = {0.25, 9, 0};
  slide.components = {true, false, false};
  scene.model.prescribed = {slide};
  const Model model(mesh, scene.model);
  ASSERT_EQ(model.profiles().size(), 2u);  // 0: the fixed groups' constant profile
  for (int node : mesh.group("clamp")->nodes) {
    const PrescribedDof* x = prescribed_dof(model, 2 * node);
    const PrescribedDof* y = prescribed_dof(model, 2 * node + 1);
    ASSERT_TRUE(x && y);
    EXPECT_EQ(x->amplitude, 0.25);
    EXPECT_EQ(x->profile, 1);
    EXPECT_EQ(y->amplitude, 0.0);  // still fixed: the prescription leaves y alone
    EXPECT_EQ(y->profile, 0);
  }
  EXPECT_EQ(model.prescribed().size(), 4u);
  for (std::size_t k = 1; k < model.prescribed().size(); ++k)
    EXPECT_LT(model.prescribed()[k - 1].dof, model.prescribed()[k].dof);
  EXPECT_EQ(model.free_dof_count(), model.dof_count() - 4);
}

TEST(ModelConstraints, HoldFixesTheGroupsConstrainedDofsAtAValue) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});
  Model model(mesh, test::cantilever("hooke").model);
  model.hold("clamp", {0.1, -0.2, 0}, {false, true, false});
  for (int node : mesh.group("clamp")->nodes) {
    const PrescribedDof& x = *prescribed_dof(model, 2 * node);
    const PrescribedDof& y = *prescribed_dof(model, 2 * node + 1);
    EXPECT_FALSE(x.held);
    EXPECT_EQ(x.amplitude, 0.0);
    EXPECT_TRUE(y.held);
    EXPECT_EQ(y.amplitude, -0.2);
    EXPECT_EQ(y.rotation, -1);
  }
}

TEST(ModelConstraints, HoldRefusesAnUnknownGroupOrAFreeDofChangingNothing) {
  const Mesh mesh = test::beam(2, "quad4", {2, 1, 1});
  Scene scene = test::cantilever("hooke");
  PrescribedSpec tip_x;
  tip_x.region = "tip";
  tip_x.components = {true, false, false};
  scene.model.prescribed = {tip_x};
  Model model(mesh, scene.model);
  try {
    model.hold("nowhere", {1, 1, 1});
    ADD_FAILURE() << "an unknown group was held";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "hold: the mesh has no group 'nowhere'");
  }
  const int first_tip = mesh.group("tip")->nodes.front();
  try {
    model.hold("tip", {1, 1, 1});
    ADD_FAILURE() << "a free dof was held";
  } catch (const InputError& error) {
    EXPECT_EQ(std::string(error.what()), "hold: node " + std::to_string(mesh.node_source_ids[first_tip]) +
                                             " of group 'tip' has a free component 1 in the scene; only dofs "
                                             "that are fixed or prescribed there can be moved");
  }
  for (const PrescribedDof& p : model.prescribed()) EXPECT_FALSE(p.held) << "dof " << p.dof;
  model.hold("tip", {0.5, 7, 0}, {true, false, false});  // the prescribed component alone
  EXPECT_EQ(prescribed_dof(model, 2 * first_tip)->amplitude, 0.5);
  EXPECT_TRUE(prescribed_dof(model, 2 * first_tip)->held);
}

}  // namespace
}  // namespace tensormass
