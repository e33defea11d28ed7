// adaptivity.refine (geometric refinement): its keys, defaults
// and ranges, and every combination it refuses, each naming the file, the
// line and the key.
#include <gtest/gtest.h>

#include "scene_test_support.hpp"
#include "tensormass/kernels/registry.hpp"
#include "tensormass/linear_solvers/linear_solver.hpp"
#include "tensormass/meshing/beam.hpp"

namespace {

using scene_test::kBaseScene;
using scene_test::load_error;
using scene_test::TempDir;
using tensormass::InputError;
using tensormass::Scene;
using test_support::expect_contains;

Scene load(const TempDir& dir, const std::string& text) {
  return tensormass::load_scene(dir.write("scene.yaml", text));
}

std::string error_of(const std::string& text) {
  TempDir dir;
  return load_error(dir.write("scene.yaml", text));
}

TEST(SceneRefine, ReadsEveryKey) {
  TempDir dir;
  const Scene scene = load(dir, kBaseScene +
                                    "adaptivity:\n"                                       // 8
                                    "  refine:\n"                                         // 9
                                    "    criteria: [{name: R_ZZ, threshold: 0.3}]\n"      // 10
                                    "    max_level: 3\n"                                  // 11
                                    "    every: 4\n"                                      // 12
                                    "    coarsen: {hysteresis: 0.25, calm_steps: 7}\n");  // 13
  EXPECT_FALSE(scene.adaptivity.enabled);                                                 // no law switching
  const tensormass::RefinementSettings& r = scene.refinement;
  EXPECT_TRUE(r.enabled);
  EXPECT_EQ(r.threshold, 0.3);
  EXPECT_EQ(r.max_level, 3);
  EXPECT_EQ(r.every, 4);
  EXPECT_TRUE(r.coarsen);
  EXPECT_EQ(r.hysteresis, 0.25);
  EXPECT_EQ(r.calm_steps, 7);
  EXPECT_EQ(r.line, 9);  // the key `refine`
}

TEST(SceneRefine, Defaults) {
  TempDir dir;
  const Scene scene = load(dir, kBaseScene + "adaptivity:\n  refine: {criteria: [{name: R_ZZ, threshold: 0.5}]}\n");
  const tensormass::RefinementSettings& r = scene.refinement;
  EXPECT_TRUE(r.enabled);
  EXPECT_EQ(r.max_level, 2);
  EXPECT_EQ(r.every, 1);
  EXPECT_TRUE(r.coarsen);
  EXPECT_EQ(r.hysteresis, 0.5);
  EXPECT_EQ(r.calm_steps, 5);
  EXPECT_FALSE(load(dir, kBaseScene).refinement.enabled);
  EXPECT_FALSE(load(dir, kBaseScene + "adaptivity:\n  refine: {criteria: [{name: R_ZZ, threshold: 0.5}], "
                                      "coarsen: false}\n")
                   .refinement.coarsen);
}

TEST(SceneRefine, BadValuesNameLineAndKey) {
  const std::string head = kBaseScene + "adaptivity:\n  refine:\n";  // refine's keys from line 10
  expect_contains(error_of(head + "    criteria: [{name: R_NL, threshold: 0.5}]\n"),
                  {"scene.yaml:10:", "adaptivity.refine.criteria[0].name", "'R_NL'", "R_ZZ"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 1.5}]\n"),
                  {"scene.yaml:10:", "adaptivity.refine.criteria[0].threshold", ">= 0 and <= 1", "1.5"});
  expect_contains(error_of(head + "    criteria: []\n"),
                  {"scene.yaml:10:", "adaptivity.refine.criteria", "exactly one criterion"});
  expect_contains(error_of(head + "    max_level: 2\n"),
                  {"scene.yaml:9:", "missing required key 'adaptivity.refine.criteria'"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 0.5}]\n    max_level: -1\n"),
                  {"scene.yaml:11:", "adaptivity.refine.max_level", ">= 0"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 0.5}]\n    every: 0\n"),
                  {"scene.yaml:11:", "adaptivity.refine.every", ">= 1"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 0.5}]\n    coarsen: {hysteresis: 1}\n"),
                  {"scene.yaml:11:", "adaptivity.refine.coarsen.hysteresis", "< 1"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 0.5}]\n    coarsen: {calm: 2}\n"),
                  {"scene.yaml:11:", "unknown key 'adaptivity.refine.coarsen.calm'", "calm_steps"});
  expect_contains(error_of(head + "    criteria: [{name: R_ZZ, threshold: 0.5}]\n    levels: 2\n"),
                  {"scene.yaml:11:", "unknown key 'adaptivity.refine.levels'", "max_level"});
}

TEST(SceneRefine, AcceptsLawSwitchingAlongside) {
  TempDir dir;
  const Scene scene = load(dir, kBaseScene +
                                    "adaptivity:\n"
                                    "  criteria: [{name: R_NL, threshold: 0.01}]\n"
                                    "  ladder: [hooke, neohookean]\n"
                                    "  refine: {criteria: [{name: R_ZZ, threshold: 0.5}], max_level: 1}\n");
  EXPECT_TRUE(scene.adaptivity.enabled);
  ASSERT_EQ(scene.adaptivity.criteria.size(), 1u);
  EXPECT_EQ(scene.adaptivity.criteria[0].name, "R_NL");
  EXPECT_EQ(scene.adaptivity.ladder, (std::vector<std::string>{"hooke", "neohookean"}));
  EXPECT_TRUE(scene.refinement.enabled);
  EXPECT_EQ(scene.refinement.threshold, 0.5);
  EXPECT_EQ(scene.refinement.max_level, 1);
}

TEST(SceneRefine, RefusesNodalForces) {
  expect_contains(error_of(kBaseScene + "loads:\n  nodal_forces: [{region: tip, force: [0, -1]}]\n"
                                        "adaptivity:\n  refine: {criteria: [{name: R_ZZ, threshold: 0.5}]}\n"),
                  {"scene.yaml:11:", "adaptivity.refine", "nodal_forces", "loads.pressure"});
}

TEST(SceneRefine, RunsWithPetsc) {
  if (!tensormass::petsc_available()) GTEST_SKIP() << "this build has no PETSc: solver.backend petsc fails before";
  TempDir dir;
  const Scene scene = load(
      dir, kBaseScene + "  backend: petsc\n" + "adaptivity:\n  refine: {criteria: [{name: R_ZZ, threshold: 0.5}]}\n");
  EXPECT_TRUE(scene.refinement.enabled);
}

/// validate_against_mesh: quad4 and tri3 in 2D; hex8, tet4, prism6 and pyramid5 in 3D.
std::string mesh_error(const tensormass::BeamSpec& spec) {
  TempDir dir;
  Scene scene = load(dir, kBaseScene + "adaptivity:\n  refine: {criteria: [{name: R_ZZ, threshold: 0.5}]}\n");
  try {
    tensormass::validate_against_mesh(scene, tensormass::make_beam(spec));
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

TEST(SceneRefine, RefusesMeshesItCannotRefine) {
  tensormass::BeamSpec spec;
  spec.cells = {4, 2, 2};
  EXPECT_EQ(mesh_error(spec), "");  // quad4
  spec.phases = {{"tri3", 1.0}};
  EXPECT_EQ(mesh_error(spec), "");
  spec.order = 2;
  expect_contains(mesh_error(spec), {"scene.yaml:9:", "adaptivity.refine", "quad4 and tri3", "tri6"});
  tensormass::BeamSpec solid;
  solid.dim = 3;
  solid.cells = {4, 2, 2};
  for (const char* cut : {"hex8", "tet6", "prism6", "pyramid5"}) {
    solid.phases = {{cut, 1.0}};
    EXPECT_EQ(mesh_error(solid), "") << cut;
  }
  solid.phases = {{"hex8", 1.0}};
  solid.order = 2;
  expect_contains(mesh_error(solid),
                  {"scene.yaml:9:", "adaptivity.refine", "hex8, tet4, prism6 and pyramid5", "hex20"});
}

}  // namespace
