// check_groups (scene_groups.cpp) against a small hand-built mesh: every
// region names a group of the mesh, with facets where a load needs them.
#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace {

using scene_test::TempDir;
using test_support::expect_contains;
using tensormass::Group;
using tensormass::InputError;
using tensormass::Mesh;
using tensormass::Scene;

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

/// Groups only: check_groups does not look at the elements.
Mesh groups_mesh() {
  Mesh mesh;
  mesh.dim = 2;
  mesh.source = "beam.msh";
  mesh.rest_positions = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0};
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
    tensormass::check_groups(scene, groups_mesh());
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

TEST(SceneGroups, AllRegionsExist) {
  TempDir dir;
  const Scene scene = tensormass::load_scene(dir.write("scene.yaml", kGroupsScene));
  EXPECT_NO_THROW(tensormass::check_groups(scene, groups_mesh()));
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
  only_fixed.loads.nodal_forces.clear();
  try {
    tensormass::check_groups(only_fixed, groups_mesh());
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:5: fixed[1]: no group 'wall'", "(groups: clamp, top, tip)"});
  }
  Scene only_force = scene;
  only_force.fixed.pop_back();
  try {
    tensormass::check_groups(only_force, groups_mesh());
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
    tensormass::check_groups(scene, mesh);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"scene.yaml:3: materials[0].region", "the mesh has no groups"});
  }
}

}  // namespace
