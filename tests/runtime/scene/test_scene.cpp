// The scene reader's entry points (tensormass/scene/scene.hpp) where the
// other scene tests leave them: a document that is not a map, relative paths
// taken from the scene's folder, and the schema scene_schema() lists. The
// keys and values themselves: test_scene_load.cpp, test_scene_errors.cpp,
// test_scene_overrides.cpp, test_scene_refine.cpp; the documented schema:
// test_scene_reference.cpp.
#include <gtest/gtest.h>

#include <algorithm>
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
  EXPECT_EQ(material->second, (std::vector<std::string>{"region", "law", "split", "density"}));
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
