// The one validation pass (scene.cpp while reading, scene_validation.cpp
// against the mesh): every region names a group of the mesh, with facets
// where a load needs them; every cell has a material and a kernel; pressure
// facets are faces of cells; a static solve has a constraint; the explicit
// solver refuses stiffness damping while reading.
#include <gtest/gtest.h>

#include "scene_test_support.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using scene_test::kBaseScene;
using scene_test::load_error;
using scene_test::replaced;
using scene_test::TempDir;
using tensormass::Group;
using tensormass::InputError;
using tensormass::Mesh;
using tensormass::Scene;
using test_support::expect_contains;

Group make_group(const std::string& name, int dim, std::vector<int> nodes, bool with_facet) {
  Group g;
  g.name = name;
  g.dim = dim;
  g.nodes = std::move(nodes);
  if (with_facet) {
    g.facets.nodes = {g.nodes[0], g.nodes[1]};
    g.facets.offsets = {0, 2};
    g.facets.orders = {1};
  }
  return g;
}

/// One unit quad and its groups: the smallest mesh every check of
/// validate_against_mesh accepts for kGroupsScene.
Mesh groups_mesh() {
  Mesh mesh;
  mesh.dim = 2;
  mesh.source = "beam.msh";
  mesh.rest_positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
  tensormass::ElementBlock quad;
  quad.element = tensormass::Registry::instance().element("quad4");
  quad.connectivity = {0, 1, 2, 3};
  quad.source_ids = {1};
  mesh.blocks = {quad};
  mesh.groups = {make_group("clamp", 1, {0, 3}, true), make_group("top", 1, {2, 3}, true),
                 make_group("tip", 0, {1}, false)};
  return mesh;
}

const char* const kGroupsScene = R"(mesh: beam.msh
materials:
  - {region: top, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}
  - {region: all, law: hooke, young: 1.0e6, poisson: 0.3, density: 1000}
fixed: [clamp]
prescribed:
  - {region: top, displacement: [0, 0.1]}
loads:
  nodal_forces: [{region: tip, force: [0, -1]}]
  pressure: [{region: top, pressure: 10}]
solver: {type: static}
)";

std::string groups_error(const TempDir& dir, const std::vector<std::string>& overrides) {
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", kGroupsScene), overrides);
  try {
    tensormass::validate_against_mesh(scene, groups_mesh());
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(SceneGroups, AllRegionsExist) {
  TempDir dir;
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", kGroupsScene));
  EXPECT_NO_THROW(tensormass::validate_against_mesh(scene, groups_mesh()));
}

TEST(SceneGroups, MissingGroupsNameKeyLineAndGroups) {
  TempDir dir;
  const std::string groups = "(groups: clamp, top, tip)";
  expect_contains(groups_error(dir, {"materials.0.region=tumor"}),
                  {"scene.yaml", "materials[0].region", "no group 'tumor' in beam.msh", groups});
  expect_contains(groups_error(dir, {"prescribed.0.region=lung"}),
                  {"scene.yaml", "prescribed[0].region", "'lung'", groups});
  expect_contains(groups_error(dir, {"loads.nodal_forces.0.region=tail"}),
                  {"scene.yaml", "loads.nodal_forces[0].region", "'tail'", groups});
  expect_contains(groups_error(dir, {"loads.pressure.0.region=bottom"}),
                  {"scene.yaml", "loads.pressure[0].region", "'bottom'", groups});
}

TEST(SceneGroups, LinesComeFromTheFile) {
  TempDir dir;
  std::string text = scene_test::replaced(kGroupsScene, "fixed: [clamp]", "fixed: [clamp, wall]");
  text = scene_test::replaced(text, "region: tip", "region: tap");
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", text));
  Scene only_fixed = scene;
  only_fixed.model.loads.nodal_forces.clear();
  try {
    tensormass::validate_against_mesh(only_fixed, groups_mesh());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:5: fixed[1]: no group 'wall'", "(groups: clamp, top, tip)"});
  }
  Scene only_force = scene;
  only_force.model.fixed.pop_back();
  try {
    tensormass::validate_against_mesh(only_force, groups_mesh());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:9: loads.nodal_forces[0].region: no group 'tap'"});
  }
}

TEST(SceneGroups, AllIsNotAGroupForOtherKeys) {
  TempDir dir;
  expect_contains(groups_error(dir, {"fixed=[all]"}), {"fixed[0]", "no group 'all'"});
}

TEST(SceneGroups, PressureNeedsFacets) {
  TempDir dir;
  expect_contains(groups_error(dir, {"loads.pressure.0.region=tip"}),
                  {"scene.yaml", "loads.pressure[0].region", "'tip'", "no boundary facets"});
}

TEST(SceneGroups, MeshWithoutGroups) {
  TempDir dir;
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", kGroupsScene));
  Mesh mesh = groups_mesh();
  mesh.groups.clear();
  try {
    tensormass::validate_against_mesh(scene, mesh);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:3: materials[0].region", "the mesh has no groups"});
  }
}

/// A 4 x 2 quad beam (order 1 or 2) with the groups clamp, tip and body.
Mesh beam(int order = 1) {
  tensormass::BeamSpec spec;
  spec.cells = {4, 2, 1};
  spec.size = {2.0, 1.0, 1.0};
  spec.order = order;
  return tensormass::make_beam(spec);
}

/// The message validate_against_mesh throws for `text` on `mesh` (a failure when none).
std::string mesh_error(const TempDir& dir, const std::string& text, const Mesh& mesh) {
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", text));
  try {
    tensormass::validate_against_mesh(scene, mesh);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(SceneValidation, BaseSceneOnBeamPasses) {
  TempDir dir;
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", kBaseScene));
  EXPECT_NO_THROW(tensormass::validate_against_mesh(scene, beam()));
}

TEST(SceneValidation, ExplicitSolverRefusesStiffnessDampingWhileReading) {
  TempDir dir;
  const std::string text = replaced(kBaseScene, "  type: static\n  load_steps: 10\n",
                                    "  type: explicit\n  dt: 1.0e-4\n  steps: 10\n  damping: {stiffness: 0.01}\n");
  expect_contains(load_error(dir.write("scene.yaml", text)),
                  {"scene.yaml:9:", "solver.damping.stiffness", "explicit", "damping.mass"});
  // The same key is fine for the implicit solver.
  const std::string implicit = replaced(text, "type: explicit", "type: implicit");
  EXPECT_NO_THROW(tensormass::load_scene(dir.write("implicit.yaml", implicit)));
}

TEST(SceneValidation, CellWithoutMaterialIsNamed) {
  TempDir dir;
  const std::string text = replaced(kBaseScene, "region: all", "region: tip");
  expect_contains(mesh_error(dir, text, beam()), {"scene.yaml", "no material region contains", "quad4", "region: all"});
}

TEST(SceneValidation, MissingKernelNamesMaterialLineAndSplit) {
  TempDir dir;
  // The tensor split is offered for first-order elements only.
  const std::string text = replaced(kBaseScene, "law: stvk,", "law: hooke, split: tensor,");
  expect_contains(mesh_error(dir, text, beam(2)),
                  {"scene.yaml:3:", "materials[0]", "no kernel for law 'hooke', element 'quad8', split 'tensor'"});
  EXPECT_NO_THROW(tensormass::validate_against_mesh(tensormass::load_scene(dir.write("linear.yaml", text)), beam(1)));
}

TEST(SceneValidation, PressureFacetOutsideEveryCellIsRefused) {
  TempDir dir;
  Mesh mesh = beam();
  // A "facet" joining the clamped corner to the far corner: no cell has both.
  tensormass::Group diagonal;
  diagonal.name = "diagonal";
  diagonal.dim = 1;
  diagonal.nodes = {0, mesh.node_count() - 1};
  diagonal.facets.nodes = diagonal.nodes;
  diagonal.facets.offsets = {0, 2};
  diagonal.facets.orders = {1};
  mesh.groups.push_back(diagonal);
  const std::string text = kBaseScene + "loads:\n  pressure: [{region: diagonal, pressure: 10}]\n";
  expect_contains(mesh_error(dir, text, mesh),
                  {"scene.yaml:9:", "loads.pressure[0]", "group 'diagonal'", "facet 0 is not a face of any element"});
}

TEST(SceneValidation, StaticSolveNeedsAConstraint) {
  TempDir dir;
  const std::string text = replaced(kBaseScene, "fixed: [clamp]\n", "");
  expect_contains(mesh_error(dir, text, beam()), {"scene.yaml", "a static solve needs fixed or prescribed nodes"});
}

TEST(SceneValidation, EveryDofConstrainedIsRefused) {
  TempDir dir;
  const std::string text = replaced(kBaseScene, "fixed: [clamp]", "fixed: [clamp, body]");
  expect_contains(mesh_error(dir, text, beam()), {"scene.yaml", "every degree of freedom is constrained"});
}

}  // namespace

namespace {

TEST(SceneGroups, RotationOfA2DMeshMustTurnAboutZ) {
  TempDir dir;
  const std::string rotating = replaced(kGroupsScene, "  - {region: top, displacement: [0, 0.1]}",
                                        "  - {region: top, rotation: {axis: [1, 0, 0], angle: 30}}");
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", rotating));
  try {
    tensormass::validate_against_mesh(scene, groups_mesh());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:7: prescribed[0].rotation.axis", "about z"});
  }
  const Scene in_plane =
      tensormass::load_scene(dir.write("scene.yaml", replaced(rotating, "axis: [1, 0, 0], ", "centre: [0.5, 0.5], ")));
  EXPECT_NO_THROW(tensormass::validate_against_mesh(in_plane, groups_mesh()));
}

}  // namespace
