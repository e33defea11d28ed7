// The scene reader's entry points (tensormass/scene/scene.hpp) where the
// other scene tests leave them: a document that is not a map, relative paths
// taken from the scene's folder, and the schema scene_schema() lists. The
// keys and values themselves: test_scene_load.cpp, test_scene_errors.cpp,
// test_scene_overrides.cpp, test_scene_refine.cpp; the documented schema:
// test_scene_reference.cpp. Fibre fields of the laws that read them.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <string>

#include "scene_test_support.hpp"
#include "tensormass/scene/scene.hpp"

namespace {

using tensormass::Scene;

/// The message of the InputError parse_scene throws for `text` ("" when it throws none).
std::string parse_error(const std::string& text, const std::vector<std::string>& overrides = {}) {
  try {
    tensormass::parse_scene(text, "cases/scene.yaml", overrides);
  } catch (const tensormass::InputError& error) {
    return error.what();
  }
  return "";
}

TEST(Scene, ADocumentThatIsNotAMapIsRefused) {
  EXPECT_EQ(parse_error("- mesh: beam.msh\n- solver: {}\n"),
            "cases/scene.yaml:1: a scene is a map of keys (mesh, materials, solver, ...), got a list");
  EXPECT_EQ(parse_error("beam.msh\n"),
            "cases/scene.yaml:1: a scene is a map of keys (mesh, materials, solver, ...), got 'beam.msh'");
}

TEST(Scene, TheMeshAndOutputAreTakenFromTheScenesFolder) {
  const Scene scene = tensormass::parse_scene(scene_test::kBaseScene, "cases/scene.yaml", {"output.directory=out"});
  EXPECT_EQ(scene.mesh, "cases/beam.msh");
  EXPECT_EQ(scene.path, "cases/scene.yaml");
  const Scene absolute = tensormass::parse_scene(
      scene_test::replaced(scene_test::kBaseScene, "beam.msh", "/data/beam.msh"), "cases/s.yaml");
  EXPECT_EQ(absolute.mesh, "/data/beam.msh");
}

TEST(Scene, OverridesApplyBeforeTheRequiredKeysAreChecked) {
  const std::string without_mesh = scene_test::replaced(scene_test::kBaseScene, "mesh: beam.msh\n", "");
  EXPECT_EQ(parse_error(without_mesh), "cases/scene.yaml:1: missing required key 'mesh'");
  EXPECT_EQ(tensormass::parse_scene(without_mesh, "cases/scene.yaml", {"mesh=other.msh"}).mesh, "cases/other.msh");
}

TEST(SceneSchema, ListsEveryMapOnceWithDistinctKeys) {
  const auto schema = tensormass::scene_schema();
  std::set<std::string> paths;
  for (const auto& [path, keys] : schema) {
    EXPECT_TRUE(paths.insert(path).second) << "twice: '" << path << "'";
    EXPECT_EQ(std::set<std::string>(keys.begin(), keys.end()).size(), keys.size()) << "a key twice in '" << path << "'";
    EXPECT_FALSE(keys.empty()) << path;
  }
  for (const char* path :
       {"", "materials[]", "solver", "solver.linear", "loads.profile", "adaptivity.refine", "output"})
    EXPECT_EQ(paths.count(path), 1u) << "missing: '" << path << "'";
  const auto top = std::find_if(schema.begin(), schema.end(), [](const auto& entry) { return entry.first.empty(); });
  ASSERT_NE(top, schema.end());
  EXPECT_EQ(top->second, (std::vector<std::string>{"mesh", "materials", "fixed", "prescribed", "loads", "solver",
                                                   "adaptivity", "output"}));
}

TEST(SceneSchema, AMaterialListsItsOwnKeysNotItsLawsConstants) {
  const auto schema = tensormass::scene_schema();
  const auto material =
      std::find_if(schema.begin(), schema.end(), [](const auto& entry) { return entry.first == "materials[]"; });
  ASSERT_NE(material, schema.end());
  EXPECT_EQ(material->second, (std::vector<std::string>{"region", "law", "split", "density", "fibres", "fibres2"}));
  // The reader still takes a law's constants in a material.
  EXPECT_EQ(parse_error(scene_test::kBaseScene), "");
}

TEST(SceneSchema, EveryMapOfTheSchemaTakesOverridesOfItsKeys) {
  // An override of a key the schema lists is never refused as unknown.
  for (const auto& [path, keys] : tensormass::scene_schema()) {
    if (path.find("[]") != std::string::npos) continue;  // list items need a list to index
    for (const std::string& key : keys) {
      const std::string typed = (path.empty() ? "" : path + ".") + key;
      const std::string message = parse_error(scene_test::kBaseScene, {typed + "=~"});
      EXPECT_EQ(message.find("unknown key"), std::string::npos) << typed << ": " << message;
    }
  }
}

}  // namespace

namespace {

const std::string kFibreScene = scene_test::replaced(
    scene_test::kBaseScene, "law: stvk, young: 1.0e6, poisson: 0.3,",
    "law: transversely_isotropic_mooney_rivlin, c10: 1.0e3, c01: 0, eta: 5.0e3, kappa: 1.0e5, FIBRES");

std::string fibre_scene(const std::string& fibres) { return scene_test::replaced(kFibreScene, "FIBRES", fibres); }

TEST(SceneFibres, ConstantFormulaAndFileFields) {
  const Scene constant = tensormass::parse_scene(fibre_scene("fibres: [1, 0, 0],"), "cases/scene.yaml");
  EXPECT_EQ(constant.model.materials[0].fibres[0].describe(), "constant (1, 0, 0)");
  EXPECT_FALSE(constant.model.materials[0].fibres[1].given());
  const Scene formula = tensormass::parse_scene(fibre_scene("fibres: [-y, x, 0],"), "cases/scene.yaml");
  EXPECT_EQ(formula.model.materials[0].fibres[0].describe(), "formula [-y, x, 0]");
  test_support::TempDir dir;
  const std::string path = dir.file("fibres.txt");
  std::ofstream(path) << "0 0 0 1 0 0\n";
  const Scene file = tensormass::parse_scene(fibre_scene("fibres: {file: " + path + "},"), "cases/scene.yaml");
  EXPECT_EQ(file.model.materials[0].fibres[0].describe(), "file " + path);
}

TEST(SceneFibres, ErrorsNameTheMaterialAndKey) {
  EXPECT_EQ(parse_error(fibre_scene("")),
            "cases/scene.yaml:3: materials[0]: law transversely_isotropic_mooney_rivlin reads a fibre direction: give "
            "`fibres: [ax, ay, az]` (or formulas of x, y, z, or {file: path})");
  EXPECT_EQ(parse_error(fibre_scene("fibres: [1, 0, 0], fibres2: [0, 1, 0],")),
            "cases/scene.yaml:3: materials[0].fibres2: law transversely_isotropic_mooney_rivlin reads one fibre "
            "family (`fibres`)");
  EXPECT_EQ(parse_error(scene_test::replaced(scene_test::kBaseScene, "density", "fibres: [1, 0, 0], density")),
            "cases/scene.yaml:3: materials[0].fibres: no law of the material reads fibre directions (stvk)");
  EXPECT_NE(parse_error(fibre_scene("fibres: [1, 0],")).find("materials[0].fibres: expected [ax, ay, az]"),
            std::string::npos);
  EXPECT_NE(parse_error(fibre_scene("fibres: [0, 0, 0],")).find("the fibre direction must be a non-zero vector"),
            std::string::npos);
  EXPECT_NE(parse_error(fibre_scene("fibres: [x, q, 0],")).find("materials[0].fibres: formula 'q': unknown name 'q'"),
            std::string::npos);
  EXPECT_NE(parse_error(fibre_scene("fibres: {path: a.csv},")).find("materials[0].fibres"), std::string::npos);
  EXPECT_NE(parse_error(fibre_scene("fibres: {file: missing.csv},")).find("cases/missing.csv"), std::string::npos);
  // The directions are not constants a user sets.
  EXPECT_NE(parse_error(fibre_scene("fibres: [1, 0, 0], fibre_x: 1,")).find("materials[0].fibre_x"), std::string::npos);
}

}  // namespace
