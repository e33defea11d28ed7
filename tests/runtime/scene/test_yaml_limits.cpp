// The bounds a scene's YAML tree keeps (scene/yaml_limits.hpp): the node
// limit growing with the document's size, nodes counted with aliases
// expanded, and the nesting depth, each refused at the line where it is passed.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "scene/yaml_limits.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {
namespace {

/// The message of the InputError check_yaml_limits throws ("" when it throws none).
std::string limit_error(const YAML::Node& root, std::size_t document_bytes) {
  try {
    check_yaml_limits(root, "scene.yaml", document_bytes);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

/// A list of `n` scalars built in memory (no marks): n + 1 nodes.
YAML::Node list_of(std::size_t n) {
  YAML::Node list(YAML::NodeType::Sequence);
  for (std::size_t i = 0; i < n; ++i) list.push_back(0);
  return list;
}

/// `levels` lists nested in flow style on one line: "[[[]]]".
std::string nested_lists(int levels) { return std::string(levels, '[') + std::string(levels, ']'); }

/// The root map and `levels` maps nested in it, block style: the value of key
/// kJ is the map at depth J + 1, starting on line J + 2.
std::string nested_maps(int levels) {
  std::string text;
  for (int k = 0; k < levels; ++k) text += std::string(k, ' ') + "k" + std::to_string(k) + ":\n";
  return text + std::string(levels, ' ') + "leaf: 1\n";
}

TEST(YamlLimits, TheNodeLimitIsAFloorOrTwentyNodesPerByte) {
  EXPECT_EQ(yaml_node_limit(0), 300000u);
  EXPECT_EQ(yaml_node_limit(15000), 300000u);
  EXPECT_EQ(yaml_node_limit(15001), 300020u);
  EXPECT_EQ(yaml_node_limit(16u << 20), 335544320u);
}

TEST(YamlLimits, APlainSceneIsWithinTheLimits) {
  const std::string text = "mesh: beam.msh\nmaterials:\n  - {region: all, law: stvk, young: 1.0e6}\nfixed: [clamp]\n";
  EXPECT_EQ(limit_error(YAML::Load(text), text.size()), "");
}

TEST(YamlLimits, ExactlyTheLimitOfNodesIsAcceptedAndOneMoreRefused) {
  EXPECT_EQ(limit_error(list_of(299999), 0), "");  // 300000 nodes with the list
  EXPECT_EQ(limit_error(list_of(300000), 0),
            "scene.yaml: the document holds more than 300000 values once its aliases are expanded (an alias "
            "bomb?); a scene lists its values plainly");
  EXPECT_EQ(limit_error(list_of(300000), 15001), "");  // a larger document may hold 300020
}

TEST(YamlLimits, AliasesCountOncePerUse) {
  // Nine levels of ten aliases stand for 10^9 values in a few hundred bytes.
  std::string text = "l0: &l0 [0, 0, 0, 0, 0, 0, 0, 0, 0, 0]\n";
  for (int level = 1; level <= 8; ++level) {
    const std::string previous = "*l" + std::to_string(level - 1);
    text += "l" + std::to_string(level) + ": &l" + std::to_string(level) + " [";
    for (int i = 0; i < 10; ++i) text += (i ? ", " : "") + previous;
    text += "]\n";
  }
  const std::string message = limit_error(YAML::Load(text), text.size());
  EXPECT_EQ(message.rfind("scene.yaml:1: the document holds more than 300000 values once its aliases are expanded", 0),
            0u)
      << message;  // the 300001st value is one of the aliased zeros of line 1
}

TEST(YamlLimits, SixtyFourNestedListsAreAcceptedAndSixtyFiveRefused) {
  EXPECT_EQ(limit_error(YAML::Load(nested_lists(64)), 128), "");
  EXPECT_EQ(limit_error(YAML::Load(nested_lists(65)), 130), "scene.yaml:1: maps and lists nest deeper than 64 levels");
}

TEST(YamlLimits, TooDeepANestingIsNamedByTheLineOfTheMapPastTheLimit) {
  EXPECT_EQ(limit_error(YAML::Load(nested_maps(63)), 3000), "");  // depths 0 .. 63
  // The values of k0 .. k63 are maps at depths 1 .. 64: the one at depth 64,
  // the value of k63, starts on line 65 (its key "leaf").
  EXPECT_EQ(limit_error(YAML::Load(nested_maps(64)), 3000), "scene.yaml:65: maps and lists nest deeper than 64 levels");
}

TEST(YamlLimits, ScalarsDeepInsideTheLimitDoNotCountAsNesting) {
  // 64 lists hold a scalar at depth 64: a value, not a level of nesting.
  EXPECT_EQ(limit_error(YAML::Load(std::string(64, '[') + "7" + std::string(64, ']')), 129), "");
}

}  // namespace
}  // namespace tensormass::scene_yaml
