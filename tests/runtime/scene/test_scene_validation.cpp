// The one validation pass: what load_scene refuses while reading without a
// mesh (explicit solver with stiffness damping), and what
// validate_against_mesh refuses on a real beam mesh (materials, kernels,
// pressure facets, constraints), each message naming the file, line and key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "scene_test_support.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using scene_test::kBaseScene;
using scene_test::load_error;
using scene_test::replaced;
using scene_test::TempDir;
using tensormass::InputError;
using tensormass::Mesh;
using tensormass::Scene;

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

void expect_contains(const std::string& message, const std::vector<std::string>& parts) {
  for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << part << " in: " << message;
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
