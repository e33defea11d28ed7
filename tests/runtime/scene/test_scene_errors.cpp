// Every validation error class: the message names the file, the line and the key.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <chrono>
#include <filesystem>

#include "scene_test_support.hpp"

namespace {

using scene_test::kBaseScene;
using scene_test::load_error;
using scene_test::replaced;
using scene_test::TempDir;

struct ErrorCase {
  std::string name;
  std::string text;                   ///< the scene file
  std::vector<std::string> expected;  ///< substrings of the message ("scene.yaml:3", the key, ...)
};

/// The base scene with `from` replaced by `to`.
ErrorCase edit(std::string name, const std::string& from, const std::string& to, std::vector<std::string> expected) {
  return {std::move(name), replaced(kBaseScene, from, to), std::move(expected)};
}

/// The base scene with `lines` appended (the first appended line is line 8).
ErrorCase append(std::string name, const std::string& lines, std::vector<std::string> expected) {
  return {std::move(name), kBaseScene + lines, std::move(expected)};
}

std::vector<ErrorCase> unknown_key_cases() {
  return {
      append("UnknownTopKey", "solvr: {type: static}\n", {"scene.yaml:8:", "unknown key 'solvr'", "known: mesh,"}),
      append("UnknownSolverKey", "  dtt: 0.1\n", {"scene.yaml:8:", "unknown key 'solver.dtt'", "load_steps"}),
      edit("UnknownMaterialKey", "density: 1000", "density: 1000, yuong: 3",
           {"scene.yaml:3:", "unknown key 'materials[0].yuong'", "young"}),
      append("UnknownNestedKey", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  downgrade: {calm: 3}\n",
             {"scene.yaml:10:", "unknown key 'adaptivity.downgrade.calm'", "calm_steps"}),
      append("DuplicateKey", "  load_steps: 3\n", {"scene.yaml:8:", "duplicate key 'solver.load_steps'"}),
  };
}

std::vector<ErrorCase> type_cases() {
  return {
      edit("NotANumber", "young: 1.0e6", "young: abc",
           {"scene.yaml:3: materials[0].young: expected a number, got 'abc'"}),
      edit("NotFinite", "young: 1.0e6", "young: .inf", {"scene.yaml:3:", "materials[0].young", "finite"}),
      edit("NaN", "poisson: 0.3", "poisson: nan", {"scene.yaml:3:", "materials[0].poisson", "finite"}),
      edit("Overflow", "young: 1.0e6", "young: 1e999", {"scene.yaml:3:", "materials[0].young", "finite"}),
      edit("NotAnInteger", "load_steps: 10", "load_steps: 2.5", {"scene.yaml:7:", "solver.load_steps", "integer"}),
      edit("ListForANumber", "young: 1.0e6", "young: [1]", {"scene.yaml:3:", "materials[0].young", "a list"}),
      edit("ScalarForASection", "solver:\n  type: static\n  load_steps: 10\n", "solver: static\n",
           {"scene.yaml:5:", "solver", "expected a map", "'static'"}),
      edit("MaterialsNotAList", "materials:\n  - {region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}",
           "materials: stvk", {"scene.yaml:2:", "materials", "expected a list"}),
      edit("FixedNotAList", "fixed: [clamp]", "fixed: clamp", {"scene.yaml:4:", "fixed", "expected a list"}),
      edit("EmptyString", "region: all", "region: ''", {"scene.yaml:3:", "materials[0].region", "empty"}),
  };
}

std::vector<ErrorCase> range_cases() {
  return {
      edit("YoungZero", "young: 1.0e6", "young: 0", {"scene.yaml:3:", "materials[0].young", "> 0"}),
      edit("PoissonHalf", "poisson: 0.3", "poisson: 0.5", {"scene.yaml:3:", "materials[0].poisson", "< 0.5"}),
      edit("PoissonMinusOne", "poisson: 0.3", "poisson: -1", {"scene.yaml:3:", "materials[0].poisson", "> -1"}),
      edit("DensityNegative", "density: 1000", "density: -2", {"scene.yaml:3:", "materials[0].density", "> 0"}),
      edit("LoadStepsZero", "load_steps: 10", "load_steps: 0", {"scene.yaml:7:", "solver.load_steps", ">= 1"}),
      append("ToleranceOne", "  tolerance: 1\n", {"scene.yaml:8:", "solver.tolerance", "< 1"}),
      append("MaxIterationsZero", "  max_iterations: 0\n", {"scene.yaml:8:", "solver.max_iterations", ">= 1"}),
      append("ThreadsNegative", "  threads: -1\n", {"scene.yaml:8:", "solver.threads", ">= 0"}),
      append("DampingNegative", "  damping: {mass: -0.1}\n", {"scene.yaml:8:", "solver.damping.mass", ">= 0"}),
      append("LinearTolerance", "  linear: {tolerance: 0}\n", {"scene.yaml:8:", "solver.linear.tolerance", "> 0"}),
      append("NewtonZero", "  newton_iterations: 0\n", {"scene.yaml:8:", "solver.newton_iterations", ">= 1"}),
      append("ThresholdNegative", "adaptivity:\n  criteria: [{name: R_EL, threshold: -0.1}]\n",
             {"scene.yaml:9:", "adaptivity.criteria[0].threshold", ">= 0"}),
      append("HysteresisOne", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  downgrade: {hysteresis: 1}\n",
             {"scene.yaml:10:", "adaptivity.downgrade.hysteresis", "< 1"}),
      append("CalmStepsZero", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  downgrade: {calm_steps: 0}\n",
             {"scene.yaml:10:", "adaptivity.downgrade.calm_steps", ">= 1"}),
      append("EveryZero", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  every: 0\n",
             {"scene.yaml:10:", "adaptivity.every", ">= 1"}),
      append("BlendNegative", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  blend_steps: -1\n",
             {"scene.yaml:10:", "adaptivity.blend_steps", ">= 0"}),
      append("OutputEveryNegative", "output:\n  every: -1\n", {"scene.yaml:9:", "output.every", ">= 0"}),
      append("RampDurationZero", "loads:\n  profile: {type: ramp, duration: 0}\n",
             {"scene.yaml:9:", "loads.profile.duration", "> 0"}),
  };
}

std::vector<ErrorCase> name_cases() {
  return {
      edit("UnknownLaw", "law: stvk", "law: rubber", {"scene.yaml:3:", "materials[0].law", "'rubber'", "stvk"}),
      edit("UnknownSplit", "density: 1000", "density: 1000, split: halves",
           {"scene.yaml:3:", "materials[0].split", "'halves'", "whole"}),
      edit("UnknownSolverType", "type: static", "type: quasi", {"scene.yaml:6:", "solver.type", "'quasi'", "implicit"}),
      append("UnknownLinearType", "  linear: {type: lu}\n", {"scene.yaml:8:", "solver.linear.type", "'lu'", "cg"}),
      append("UnknownCriterion", "adaptivity:\n  criteria: [{name: R_X, threshold: 1}]\n",
             {"scene.yaml:9:", "adaptivity.criteria[0].name", "'R_X'", "R_VLX"}),
      append("UnknownAction", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  action: refine\n",
             {"scene.yaml:10:", "adaptivity.action", "'refine'", "upgrade"}),
      append("UnknownLadderLaw", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  ladder: [hooke, ogden]\n",
             {"scene.yaml:10:", "adaptivity.ladder[1]", "'ogden'", "neohookean"}),
      append("LadderOneLaw", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  ladder: [hooke]\n",
             {"scene.yaml:10:", "adaptivity.ladder", "at least two laws"}),
      append("LadderLawTwice",
             "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  ladder: [hooke, stvk, hooke]\n",
             {"scene.yaml:10:", "adaptivity.ladder[2]", "twice"}),
      append("RungOffTheLadder",
             "adaptivity:\n  criteria: [{name: R_EL, threshold: 1, rung: corotational}]\n  ladder: [hooke, stvk]\n",
             {"scene.yaml:9:", "adaptivity.criteria[0].rung", "not on the ladder", "hooke, stvk"}),
      append("RungIsTheFirstLaw",
             "adaptivity:\n  criteria: [{name: R_EL, threshold: 1, rung: hooke}]\n  ladder: [hooke, stvk]\n",
             {"scene.yaml:9:", "adaptivity.criteria[0].rung", "first law"}),
      append("RungUnknownLaw", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1, rung: ogden}]\n",
             {"scene.yaml:9:", "adaptivity.criteria[0].rung", "'ogden'"}),
      append("LadderNotAList", "adaptivity:\n  criteria: [{name: R_EL, threshold: 1}]\n  ladder: stvk\n",
             {"scene.yaml:10:", "adaptivity.ladder", "list of laws"}),
      append("UnknownProfile", "loads:\n  profile: square\n", {"scene.yaml:9:", "loads.profile", "'square'", "ramp"}),
      append("CriterionTwice",
             "adaptivity:\n  criteria:\n    - {name: R_EL, threshold: 1}\n    - {name: R_EL, threshold: 2}\n",
             {"scene.yaml:11:", "adaptivity.criteria[1]", "twice"}),
  };
}

std::vector<ErrorCase> vector_cases() {
  return {
      append("GravityOneComponent", "loads:\n  gravity: [1]\n", {"scene.yaml:9:", "loads.gravity", "2 or 3", "got 1"}),
      append("GravityFourComponents", "loads:\n  gravity: [1, 2, 3, 4]\n", {"scene.yaml:9:", "loads.gravity", "got 4"}),
      append("GravityScalar", "loads:\n  gravity: 9.81\n", {"scene.yaml:9:", "loads.gravity", "list of 2 or 3"}),
      append("ForceNotNumbers", "loads:\n  nodal_forces: [{region: tip, force: [0, x]}]\n",
             {"scene.yaml:9:", "loads.nodal_forces[0].force[1]", "'x'"}),
      append("DisplacementOneComponent", "prescribed:\n  - {region: top, displacement: [0]}\n",
             {"scene.yaml:9:", "prescribed[0].displacement", "2 or 3"}),
      append("NeitherDisplacementNorRotation", "prescribed:\n  - {region: top}\n",
             {"scene.yaml:9:", "missing required key 'prescribed[0].displacement'", "or 'rotation'"}),
      append("RotationWithoutAngle", "prescribed:\n  - {region: top, rotation: {axis: [1, 0, 0]}}\n",
             {"scene.yaml:9:", "prescribed[0].rotation.angle"}),
      append("RotationZeroAxis", "prescribed:\n  - {region: top, rotation: {axis: [0, 0, 0], angle: 90}}\n",
             {"scene.yaml:9:", "prescribed[0].rotation.axis", "must not be zero"}),
      append("RotationUnknownKey", "prescribed:\n  - {region: top, rotation: {angle: 90, center: [0, 0]}}\n",
             {"scene.yaml:9:", "unknown key 'prescribed[0].rotation.center'", "centre"}),
      append("PredictorUnknown", "  predictor: linear\n", {"scene.yaml:8:", "solver.predictor", "velocity, none"}),
      append("ProjectHessianNotABoolean", "  project_hessian: yes please\n",
             {"scene.yaml:8:", "solver.project_hessian", "true or false"}),
  };
}

std::vector<ErrorCase> missing_cases() {
  return {
      edit("MissingMesh", "mesh: beam.msh\n", "", {"scene.yaml:1:", "missing required key 'mesh'"}),
      edit("MissingSolverType", "  type: static\n", "", {"scene.yaml:5:", "missing required key 'solver.type'"}),
      edit("MissingSolver", "solver:\n  type: static\n  load_steps: 10\n", "",
           {"scene.yaml:1:", "missing required key 'solver'"}),
      edit("MissingLaw", "law: stvk, ", "", {"scene.yaml:3:", "missing required key 'materials[0].law'"}),
      edit("MissingYoung", "young: 1.0e6, ", "",
           {"scene.yaml:3:", "materials[0]", "law stvk needs the constant 'young'", "its parameters: young, poisson"}),
      edit("MissingValue", "mesh: beam.msh", "mesh:", {"scene.yaml:1:", "mesh", "missing value"}),
      edit("EmptyMaterials", "materials:\n  - {region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}",
           "materials: []", {"scene.yaml:2:", "materials", "at least one"}),
      edit("MissingDt", "type: static", "type: implicit",
           {"scene.yaml:5:", "missing required key 'solver.dt'", "implicit"}),
      edit("MissingSteps", "type: static", "type: explicit\n  dt: 0.001",
           {"scene.yaml:5:", "missing required key 'solver.steps'", "explicit"}),
      append("EmptyCriteria", "adaptivity:\n  criteria: []\n",
             {"scene.yaml:9:", "adaptivity.criteria", "at least one"}),
      append("MissingCriteria", "adaptivity:\n  every: 2\n",
             {"scene.yaml:8:", "missing required key 'adaptivity.criteria'"}),
      append("MissingPressureValue", "loads:\n  pressure: [{region: top}]\n",
             {"scene.yaml:9:", "missing required key 'loads.pressure[0].pressure'"}),
      append("MissingProfileType", "loads:\n  profile: {duration: 2}\n",
             {"scene.yaml:9:", "missing required key 'loads.profile.type'"}),
  };
}

std::vector<ErrorCase> file_cases() {
  return {
      {"EmptyFile", "", {"scene.yaml:1:", "empty"}},
      {"OnlyComments", "# nothing here\n", {"scene.yaml:1:", "empty"}},
      {"NotAMap", "- mesh\n- solver\n", {"scene.yaml:1:", "map of keys"}},
      {"SyntaxError",
       "mesh: beam.msh\nmaterials: [\n  {law: stvk\nsolver: {type: static}\n",
       {"scene.yaml:", "YAML syntax error"}},
      {"BadIndentation",
       "mesh: beam.msh\nsolver:\n  type: static\n   load_steps: 3\n",
       {"scene.yaml:4:", "YAML syntax error"}},
  };
}

/// A material's constants are its law's own (mooney_rivlin: c10, c01, kappa).
std::vector<ErrorCase> constant_cases() {
  const std::string mooney = "law: mooney_rivlin, c10: 2.0e5, c01: 5.0e4, kappa: 5.0e6";
  const std::string elastic = "law: stvk, young: 1.0e6, poisson: 0.3";
  return {
      edit("ConstantOfAnotherLaw", "poisson: 0.3", "poisson: 0.3, c10: 1",
           {"scene.yaml:3:", "materials[0].c10", "not a parameter of law stvk", "young, poisson"}),
      edit("ElasticConstantsForMooneyRivlin", elastic, "law: mooney_rivlin, young: 1.0e6, poisson: 0.3",
           {"scene.yaml:3:", "materials[0]", "law mooney_rivlin needs the constant 'c10'", "c10, c01, kappa"}),
      edit("MissingKappa", elastic, "law: mooney_rivlin, c10: 2.0e5, c01: 5.0e4",
           {"scene.yaml:3:", "law mooney_rivlin needs the constant 'kappa'"}),
      edit("KappaZero", elastic, "law: mooney_rivlin, c10: 2.0e5, c01: 5.0e4, kappa: 0",
           {"scene.yaml:3:", "materials[0].kappa", "must be > 0 for law mooney_rivlin", "got 0"}),
      edit("C01Negative", elastic, "law: mooney_rivlin, c10: 2.0e5, c01: -1, kappa: 5.0e6",
           {"scene.yaml:3:", "materials[0].c01", "must be >= 0"}),
      edit("YoungBesideMooneyRivlin", elastic, mooney + ", young: 1",
           {"scene.yaml:3:", "materials[0].young", "not a parameter of law mooney_rivlin"}),
      // A material on the ladder takes every ladder law's constants.
      {"LadderLawWithoutItsConstants",
       replaced(kBaseScene, elastic, "law: hooke, young: 1.0e6, poisson: 0.3") +
           "adaptivity:\n  criteria: [{name: R_EL, threshold: 0.01}]\n  ladder: [hooke, mooney_rivlin]\n",
       {"scene.yaml:3:", "law mooney_rivlin needs the constant 'c10'"}},
  };
}

std::vector<ErrorCase> all_cases() {
  std::vector<ErrorCase> all;
  for (auto cases : {unknown_key_cases(), type_cases(), range_cases(), name_cases(), vector_cases(), missing_cases(),
                     file_cases(), constant_cases()})
    all.insert(all.end(), cases.begin(), cases.end());
  return all;
}

void PrintTo(const ErrorCase& c, std::ostream* out) { *out << c.name; }

class SceneError : public ::testing::TestWithParam<ErrorCase> {};

TEST_P(SceneError, MessageNamesFileLineAndKey) {
  TempDir dir;
  const ErrorCase& c = GetParam();
  const std::string path = dir.write("scene.yaml", c.text);
  const std::string message = load_error(path);
  EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_EQ(message.rfind(dir.path().string(), 0), 0u) << message;  // starts with the file's path
  for (const std::string& part : c.expected)
    EXPECT_NE(message.find(part), std::string::npos) << part << " in: " << message;
}

// Numbered instances printed by name: ctest shows "scene.Scene/SceneError.MessageNamesFileLineAndKey/NotANumber".
INSTANTIATE_TEST_SUITE_P(Scene, SceneError, ::testing::ValuesIn(all_cases()));

TEST(SceneFile, MissingFileIsAnInputError) {
  TempDir dir;
  const std::string path = (dir.path() / "nope.yaml").string();
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open"), std::string::npos) << message;
}

TEST(SceneFile, DirectoryIsAnInputError) {
  TempDir dir;
  const std::string message = load_error(dir.path().string());
  EXPECT_NE(message.find("directory"), std::string::npos) << message;
}

/// Nine levels of ten aliases each under `fixed:`, anchored on line 2: 10^9
/// names once expanded, from a 400-byte file.
std::string alias_bomb() {
  std::string levels = "&a0 [x, x, x, x, x, x, x, x, x, x]";
  for (int level = 1; level < 9; ++level) {
    std::string previous = "*a" + std::to_string(level - 1);
    std::string items = previous;
    for (int k = 1; k < 10; ++k) items += ", " + previous;
    levels += ",\n  &a" + std::to_string(level) + " [" + items + "]";
  }
  return "mesh: beam.msh\nfixed: [\n  " + levels + "]\n";
}

TEST(SceneLimits, AliasBombIsRefusedAtOnce) {
  TempDir dir;
  const std::string path = dir.write("bomb.yaml", alias_bomb());
  const auto start = std::chrono::steady_clock::now();
  const std::string message = load_error(path);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_NE(message.find(path + ":"), std::string::npos) << message;
  EXPECT_NE(message.find("aliases are expanded"), std::string::npos) << message;
  EXPECT_LT(seconds, 10.0);
}

TEST(SceneLimits, AliasesWithinTheLimitAreRead) {
  TempDir dir;
  const std::string path =
      dir.write("aliases.yaml", replaced(kBaseScene, "fixed: [clamp]", "fixed: &clamped [clamp]\nprescribed: []"));
  EXPECT_NO_THROW(tensormass::load_scene(path));
}

TEST(SceneLimits, AliasBombInAnOverrideIsRefused) {
  TempDir dir;
  const std::string path = dir.write("scene.yaml", kBaseScene);
  std::string levels = "&b0 [x, x, x, x, x, x, x, x, x, x]";
  for (int level = 1; level < 7; ++level) {
    std::string items = "*b" + std::to_string(level - 1);
    for (int k = 1; k < 10; ++k) items += ", *b" + std::to_string(level - 1);
    levels += ", &b" + std::to_string(level) + " [" + items + "]";
  }
  const std::string message = load_error(path, {"fixed=[" + levels + "]"});
  EXPECT_NE(message.find("--set fixed"), std::string::npos) << message;
  EXPECT_NE(message.find("aliases are expanded"), std::string::npos) << message;
}

TEST(SceneLimits, DeepNestingIsRefusedWithItsLine) {
  TempDir dir;
  for (const int depth : {100, 100000}) {
    const std::string path = dir.write("deep" + std::to_string(depth) + ".yaml",
                                       kBaseScene + "loads: " + std::string(static_cast<std::size_t>(depth), '[') +
                                           std::string(static_cast<std::size_t>(depth), ']') + "\n");
    const std::string message = load_error(path);
    EXPECT_NE(message.find(path + ":8: maps and lists nest deeper than 64 levels"), std::string::npos) << message;
  }
  // A scene of one line is refused on that line, not on the one after it.
  const std::string one_line = dir.write("one_line.yaml", std::string(100000, '[') + std::string(100000, ']') + "\n");
  const std::string message = load_error(one_line);
  EXPECT_NE(message.find(one_line + ":1: maps and lists nest deeper than 64 levels"), std::string::npos) << message;
}

TEST(SceneLimits, OversizedFileIsRefusedBeforeParsing) {
  TempDir dir;
  const std::string path = dir.write("huge.yaml", kBaseScene + "# " + std::string(17u << 20, 'x') + "\n");
  const std::string message = load_error(path);
  EXPECT_NE(message.find(path + ": the scene file is larger than 16777216 bytes"), std::string::npos) << message;
}

TEST(SceneFile, OnlyRegularFilesAreRead) {
  TempDir dir;
  const std::string fifo = (dir.path() / "pipe.yaml").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::string message = load_error(fifo);
  EXPECT_NE(message.find(fifo + ": is a FIFO"), std::string::npos) << message;
  const std::string zero = (dir.path() / "zero.yaml").string();
  std::filesystem::create_symlink("/dev/zero", zero);
  message = load_error(zero);
  EXPECT_NE(message.find(zero + ": is a character device"), std::string::npos) << message;
}

}  // namespace
