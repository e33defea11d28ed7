// --set overrides: applied to the YAML tree before validation.
#include <gtest/gtest.h>

#include "scene_test_support.hpp"

namespace {

using scene_test::kBaseScene;
using scene_test::load_error;
using scene_test::TempDir;
using tensormass::Scene;

Scene load_with(const TempDir& dir, const std::vector<std::string>& overrides, const std::string& text = kBaseScene) {
  return tensormass::load_scene(dir.write("scene.yaml", text), overrides);
}

void expect_contains(const std::string& message, const std::vector<std::string>& parts) {
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  for (const std::string& part : parts) EXPECT_NE(message.find(part), std::string::npos) << part << " in: " << message;
}

TEST(SceneOverride, Number) {
  TempDir dir;
  const Scene s = load_with(dir, {"solver.load_steps=3", "solver.tolerance=1e-6"});
  EXPECT_EQ(s.solver.load_steps, 3);
  EXPECT_DOUBLE_EQ(s.solver.tolerance, 1e-6);
}

TEST(SceneOverride, ListValueCreatesMissingSection) {
  TempDir dir;
  const Scene s = load_with(dir, {"loads.gravity=[0,-1,0]"});
  EXPECT_EQ(s.model.loads.gravity, (std::array<double, 3>{0, -1, 0}));
}

TEST(SceneOverride, ListIndex) {
  TempDir dir;
  const Scene s = load_with(dir, {"materials.0.young=2e6", "fixed.0=base"});
  EXPECT_DOUBLE_EQ(s.model.materials[0].constants.at("young"), 2e6);
  EXPECT_EQ(s.model.fixed, (std::vector<std::string>{"base"}));
  EXPECT_EQ(s.model.fixed_lines, (std::vector<int>{0}));  // from the command line: no line
}

TEST(SceneOverride, NewKeysAndNewSection) {
  TempDir dir;
  const Scene s = load_with(dir, {"output.directory=/tmp/x", "output.every=5", "solver.threads=4"});
  EXPECT_EQ(s.output.directory, "/tmp/x");
  EXPECT_EQ(s.output.every, 5);
  EXPECT_EQ(s.solver.threads, 4);
}

TEST(SceneOverride, SolverTypeSwitchKeepsOtherKeys) {
  TempDir dir;
  const std::string text = kBaseScene + "  dt: 0.01\n  steps: 20\n";
  const Scene s = load_with(dir, {"solver.type=implicit"}, text);
  EXPECT_EQ(s.solver.type, tensormass::SolverType::implicit_euler);
  EXPECT_DOUBLE_EQ(s.solver.dt, 0.01);
  EXPECT_EQ(s.solver.steps, 20);
}

TEST(SceneOverride, WholeSectionAndNestedMaps) {
  TempDir dir;
  const Scene s = load_with(dir, {"adaptivity={criteria: [{name: R_EL, threshold: 0.1}]}",
                                  "adaptivity.downgrade.calm_steps=3", "solver.linear.type=cg"});
  EXPECT_TRUE(s.adaptivity.enabled);
  EXPECT_DOUBLE_EQ(s.adaptivity.criteria.at(0).threshold, 0.1);
  EXPECT_TRUE(s.adaptivity.downgrade);
  EXPECT_EQ(s.adaptivity.calm_steps, 3);
  EXPECT_EQ(s.solver.linear.type, tensormass::LinearSolverType::cg);
}

TEST(SceneOverride, LaterOverrideWins) {
  TempDir dir;
  const Scene s = load_with(dir, {"solver.load_steps=3", "solver.load_steps=4"});
  EXPECT_EQ(s.solver.load_steps, 4);
}

TEST(SceneOverride, StringsAndPathsResolveLikeTheFile) {
  TempDir dir;
  const Scene s = load_with(dir, {"mesh=other.vtu", "materials.0.law = hooke"});
  EXPECT_EQ(s.mesh, (dir.path() / "other.vtu").string());
  EXPECT_EQ(s.model.materials[0].law, "hooke");
}

TEST(SceneOverride, EmptyValueRemovesAnOptionalSetting) {
  TempDir dir;
  const Scene s = load_with(dir, {"fixed="});
  EXPECT_TRUE(s.model.fixed.empty());
}

TEST(SceneOverride, UnknownKey) {
  TempDir dir;
  expect_contains(load_error(dir.write("scene.yaml", kBaseScene), {"solver.dtt=1"}),
                  {"--set solver.dtt: unknown key 'solver.dtt' (known: type, load_steps"});
  expect_contains(load_error(dir.write("scene.yaml", kBaseScene), {"colour=red"}),
                  {"--set colour: unknown key 'colour'", "mesh"});
  expect_contains(load_error(dir.write("scene.yaml", kBaseScene), {"materials.0.yuong=1"}),
                  {"--set materials.0.yuong: unknown key 'materials[0].yuong'"});
  expect_contains(load_error(dir.write("scene.yaml", kBaseScene), {"output.dir=x"}),
                  {"--set output.dir: unknown key 'output.dir'", "directory"});
}

TEST(SceneOverride, UnknownKeyInsideAValue) {
  TempDir dir;
  expect_contains(load_error(dir.write("scene.yaml", kBaseScene), {"solver={type: static, dtt: 1}"}),
                  {"--set solver: unknown key 'solver.dtt'"});
}

TEST(SceneOverride, Malformed) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kBaseScene);
  expect_contains(load_error(path, {"solver.dt"}), {"--set solver.dt", "key=value"});
  expect_contains(load_error(path, {"=3"}), {"--set =3", "no key"});
  expect_contains(load_error(path, {"solver..dt=1"}), {"--set solver..dt", "malformed"});
  expect_contains(load_error(path, {"solver.dt=[1, 2"}), {"--set solver.dt", "YAML"});
}

TEST(SceneOverride, BadIndexOrPath) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kBaseScene);
  expect_contains(load_error(path, {"materials.3.young=1"}), {"--set materials.3.young", "'materials'", "index"});
  expect_contains(load_error(path, {"materials.x.young=1"}), {"--set materials.x.young", "index", "'x'"});
  expect_contains(load_error(path, {"solver.type.name=static"}), {"--set solver.type.name", "'solver.type'"});
  expect_contains(load_error(path, {"loads.nodal_forces.0.force=[1,2]"}),
                  {"--set loads.nodal_forces.0.force", "'loads.nodal_forces'", "whole"});
}

TEST(SceneOverride, ValidationErrorsNameTheOverride) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kBaseScene);
  expect_contains(load_error(path, {"materials.0.young=abc"}),
                  {"--set materials.0.young: materials[0].young: expected a number, got 'abc'"});
  expect_contains(load_error(path, {"solver.type=implicit"}),
                  {"scene.yaml:5:", "missing required key 'solver.dt'", "implicit"});
  expect_contains(load_error(path, {"loads.gravity=[1]"}), {"--set loads.gravity: loads.gravity:", "2 or 3"});
}

}  // namespace
