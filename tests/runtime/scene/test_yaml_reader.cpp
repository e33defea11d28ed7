// The scene reader's YAML access (scene/yaml_reader.hpp): key paths, where a
// value came from (file and line, or the --set that replaced it), parsing
// with the line of a syntax error, and typed reads whose errors name
// "FILE:LINE: path: what".
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <climits>
#include <string>

#include "scene/yaml_limits.hpp"
#include "scene/yaml_reader.hpp"
#include "support/input_error.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {
namespace {

using test_support::TempDir;

using test_support::input_error;

const char* kScene =
    "mesh: beam.msh\n"                 // 1
    "materials:\n"                     // 2
    "  - {law: stvk, young: 1.0e6}\n"  // 3
    "  - law: hooke\n"                 // 4
    "    young: 2e3\n"                 // 5
    "solver:\n"                        // 6
    "  type: static\n"                 // 7
    "  steps: 10\n"                    // 8
    "  empty:\n"                       // 9
    "  tilde: ~\n"                     // 10
    "  name: ''\n";                    // 11

/// The scene above read as "scene.yaml", its root and the solver section.
class YamlReader : public ::testing::Test {
 protected:
  YAML::Node root = read_yaml_text(kScene, "scene.yaml");
  Source source{"scene.yaml"};
  Value top{source, root, {}};
  Value solver = top.child("solver");
};

TEST(YamlPath, TextNamesKeysAndIndicesAndThePatternDropsTheIndices) {
  const Path young = Path().child("materials").item(3).child("young");
  EXPECT_EQ(young.text(), "materials[3].young");
  EXPECT_EQ(young.pattern(), "materials[].young");
  EXPECT_EQ(Path().text(), "");
  EXPECT_EQ(Path().item(0).item(1).text(), "[0][1]");
  EXPECT_EQ(Path().item(0).child("a").pattern(), "[].a");
}

TEST(YamlPath, StartsWithComparesWholeSegments) {
  const Path young = Path().child("materials").item(3).child("young");
  EXPECT_TRUE(young.starts_with(Path()));
  EXPECT_TRUE(young.starts_with(Path().child("materials").item(3)));
  EXPECT_TRUE(young.starts_with(young));
  EXPECT_FALSE(young.starts_with(Path().child("materials").item(2)));
  EXPECT_FALSE(young.starts_with(Path().child("mat")));
  EXPECT_FALSE(Path().child("materials").starts_with(young));
}

TEST(YamlText, ASyntaxErrorNamesItsLine) {
  EXPECT_EQ(input_error([] { read_yaml_text("a: 1\n  b: 2\n", "scene.yaml"); }),
            "scene.yaml:2: YAML syntax error: illegal map value");
  EXPECT_EQ(input_error([] { read_yaml_text("a: 1\nb: [1, 2\nc: {\n", "scene.yaml"); }),
            "scene.yaml:3: YAML syntax error: end of sequence flow not found");
}

TEST(YamlText, AnErrorAtTheEndOfTheTextIsOnItsLastLine) {
  // An unclosed list is found at the end of the stream, which the parser
  // places on the line after the last newline.
  for (const char* text : {"a: 1\nb: [1,\n  2\n", "a: 1\nb: [1,\n  2"})
    EXPECT_EQ(input_error([&] { read_yaml_text(text, "scene.yaml"); }),
              "scene.yaml:3: YAML syntax error: end of sequence flow not found");
  EXPECT_EQ(input_error([] { read_yaml_text("a: [1,\n", "scene.yaml"); }),
            "scene.yaml:1: YAML syntax error: end of sequence flow not found");
}

TEST(YamlText, AnEmptySceneIsRefused) {
  for (const char* text : {"", "\n\n", "# only a comment\n", "~\n"})
    EXPECT_EQ(input_error([&] { read_yaml_text(text, "scene.yaml"); }),
              "scene.yaml:1: the scene is empty (expected keys mesh, materials, solver, ...)")
        << "'" << text << "'";
}

TEST(YamlText, ATextLargerThanTheSceneLimitIsRefusedUnparsed) {
  const std::string text(kMaxYamlBytes + 1, ' ');
  EXPECT_EQ(input_error([&] { read_yaml_text(text, "big.yaml"); }),
            "big.yaml: the scene is 16777217 bytes, more than the 16777216 a scene may have");
}

TEST(YamlText, TheTreeIsCheckedAgainstTheNestingLimit) {
  const std::string text = "a: " + std::string(70, '[') + std::string(70, ']') + "\n";
  EXPECT_EQ(input_error([&] { read_yaml_text(text, "deep.yaml"); }),
            "deep.yaml:1: maps and lists nest deeper than 64 levels");
}

TEST(YamlFile, AFileIsReadAndAMissingOneNamed) {
  const TempDir dir;
  const std::string path = dir.write("scene.yaml", "mesh: beam.msh\n");
  EXPECT_EQ(read_yaml_file(path)["mesh"].as<std::string>(), "beam.msh");
  EXPECT_EQ(input_error([&] { read_yaml_file(dir.file("none.yaml")); }),
            dir.file("none.yaml") + ": cannot open scene file (No such file or directory)");
  const std::string bad = dir.write("bad.yaml", "a: 1\n\nb: : :\n");
  EXPECT_EQ(input_error([&] { read_yaml_file(bad); }), bad + ":3: YAML syntax error: illegal map value");
}

TEST_F(YamlReader, WhereNamesTheFileAndLineOfAValue) {
  EXPECT_EQ(source.where(Path().child("mesh"), root["mesh"]), "scene.yaml:1");
  EXPECT_EQ(top.child("materials").items()[1].child("young").line(), 5);
  EXPECT_EQ(source.where(Path(), YAML::Node()), "scene.yaml");  // a node made in memory has no line
}

TEST_F(YamlReader, AnOverriddenValueIsNamedByItsSetAndHasNoLine) {
  source.add_override(Path().child("solver").child("steps"), "solver.steps");
  const Value steps = solver.child("steps");
  EXPECT_EQ(steps.line(), 0);
  EXPECT_EQ(source.where(steps.path(), root["solver"]["steps"]), "--set solver.steps");
  EXPECT_EQ(input_error([&] { steps.fail("too many"); }), "--set solver.steps: solver.steps: too many");
  EXPECT_EQ(solver.child("type").line(), 7);  // a sibling keeps its line
  // A map without a line of its own, holding the override, is named by it.
  EXPECT_EQ(source.where(Path().child("solver"), YAML::Node()), "--set solver.steps");
}

TEST_F(YamlReader, TheLatestOverrideOfAPathIsTheOneNamed) {
  source.add_override(Path().child("solver"), "solver");
  source.add_override(Path().child("solver").child("type"), "solver.type");
  EXPECT_EQ(source.where(Path().child("solver").child("type"), root), "--set solver.type");
  EXPECT_EQ(source.where(Path().child("solver").child("steps"), root), "--set solver");
}

TEST_F(YamlReader, AnEmptyValueCountsAsAbsent) {
  EXPECT_TRUE(solver.child("type").present());
  EXPECT_FALSE(solver.child("empty").present());
  EXPECT_FALSE(solver.child("tilde").present());
  EXPECT_FALSE(solver.child("absent").present());
  EXPECT_TRUE(solver.child("name").present());  // '' is a value, an empty string
  EXPECT_EQ(solver.child("absent").scalar(), "");
  EXPECT_EQ(solver.child("empty").describe(), "nothing");
}

TEST_F(YamlReader, ChildOfAScalarOrAListIsRefused) {
  EXPECT_EQ(input_error([&] { top.child("mesh").child("x"); }),
            "scene.yaml:1: mesh: expected a map of keys, got 'beam.msh'");
  EXPECT_EQ(input_error([&] { top.child("materials").child("x"); }),
            "scene.yaml:2: materials: expected a map of keys, got a list");
}

TEST_F(YamlReader, RequiredNamesAMissingKeyOrAMissingValue) {
  EXPECT_EQ(solver.required("type").text(), "static");
  // A missing key is named at the map that lacks it (the key "solver:" on line 6).
  EXPECT_EQ(input_error([&] { solver.required("dt", "for solver type implicit"); }),
            "scene.yaml:6: missing required key 'solver.dt' for solver type implicit");
  EXPECT_EQ(input_error([&] { top.required("output"); }), "scene.yaml:1: missing required key 'output'");
  EXPECT_EQ(input_error([&] { solver.required("empty"); }), "scene.yaml:9: solver.empty: missing value");
  EXPECT_EQ(input_error([&] { solver.required("tilde", "(or 'x')"); }),
            "scene.yaml:10: solver.tilde: missing value (or 'x')");
}

TEST_F(YamlReader, ItemsOfAListHaveIndexedPathsAndTheirOwnLines) {
  const auto materials = top.child("materials").items();
  ASSERT_EQ(materials.size(), 2u);
  EXPECT_EQ(materials[0].path().text(), "materials[0]");
  EXPECT_EQ(materials[0].line(), 3);
  EXPECT_EQ(materials[1].line(), 4);
  EXPECT_EQ(input_error([&] { materials[1].child("law").items(); }),
            "scene.yaml:4: materials[1].law: expected a list, got 'hooke'");
  EXPECT_EQ(input_error([&] { solver.items(); }), "scene.yaml:6: solver: expected a list, got a map");
}

TEST_F(YamlReader, EntriesPairEachKeyWithItsValue) {
  const auto entries = top.child("materials").items()[1].entries();
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_EQ(entries[0].first.scalar(), "law");
  EXPECT_EQ(entries[0].second.text(), "hooke");
  EXPECT_EQ(entries[1].first.path().text(), "materials[1].young");
  EXPECT_EQ(entries[1].second.line(), 5);
  const YAML::Node complex_key = read_yaml_text("? [a, b]\n: 1\n", "scene.yaml");
  EXPECT_EQ(input_error([&] { Value(source, complex_key, {}).entries(); }),
            "scene.yaml:1: map keys must be plain names");
}

TEST_F(YamlReader, NumbersAreFiniteDecimalValues) {
  const auto value = [&](const std::string& text) {
    const YAML::Node node = YAML::Load("v: " + text);
    return Value(source, node, {}).child("v");
  };
  EXPECT_EQ(value("1.0e6").number(), 1.0e6);
  EXPECT_EQ(value("+2.5").number(), 2.5);
  EXPECT_EQ(value("-3").number(), -3.0);
  EXPECT_EQ(input_error([&] { value("abc").number(); }), "scene.yaml:1: v: expected a number, got 'abc'");
  EXPECT_EQ(input_error([&] { value("+-5").number(); }), "scene.yaml:1: v: expected a number, got '+-5'");
  EXPECT_EQ(input_error([&] { value("[1]").number(); }), "scene.yaml:1: v: expected a number, got a list");
  EXPECT_EQ(input_error([&] { value("").number(); }), "scene.yaml:1: v: expected a number, got nothing");
  for (const char* non_finite : {".inf", "-.Inf", ".NaN", "1e999"})
    EXPECT_EQ(input_error([&] { value(non_finite).number(); }),
              std::string("scene.yaml:1: v: expected a finite number, got '") + non_finite + "'");
  EXPECT_EQ(input_error([&] { value("nan").number(); }), "scene.yaml:1: v: expected a finite number, got 'nan'");
}

TEST_F(YamlReader, IntegersAcceptWholeNumbersInAnyNotationWithinIntRange) {
  const auto value = [&](const std::string& text) {
    const YAML::Node node = YAML::Load("n: " + text);
    return Value(source, node, {}).child("n");
  };
  EXPECT_EQ(value("42").integer(), 42);
  EXPECT_EQ(value("1e3").integer(), 1000);
  EXPECT_EQ(value("-7.0").integer(), -7);
  EXPECT_EQ(value("2147483647").integer(), INT_MAX);
  EXPECT_EQ(value("-2147483648").integer(), INT_MIN);
  EXPECT_EQ(input_error([&] { value("2.5").integer(); }), "scene.yaml:1: n: expected an integer, got '2.5'");
  EXPECT_EQ(input_error([&] { value("ten").integer(); }), "scene.yaml:1: n: expected an integer, got 'ten'");
  EXPECT_EQ(input_error([&] { value("{a: 1}").integer(); }), "scene.yaml:1: n: expected an integer, got a map");
  EXPECT_EQ(input_error([&] { value("2147483648").integer(); }),
            "scene.yaml:1: n: integer out of range, got '2147483648'");
  EXPECT_EQ(input_error([&] { value("-1e10").integer(); }), "scene.yaml:1: n: integer out of range, got '-1e10'");
}

TEST_F(YamlReader, TextIsANonEmptyScalar) {
  EXPECT_EQ(top.child("mesh").text(), "beam.msh");
  EXPECT_EQ(solver.child("steps").text(), "10");
  EXPECT_EQ(input_error([&] { solver.child("name").text(); }), "scene.yaml:11: solver.name: must not be empty");
  EXPECT_EQ(input_error([&] { top.child("solver").text(); }), "scene.yaml:6: solver: expected a string, got a map");
}

TEST_F(YamlReader, FailHereLeavesThePathToTheMessage) {
  EXPECT_EQ(input_error([&] { solver.child("type").fail_here("unknown key 'solver.type'"); }),
            "scene.yaml:7: unknown key 'solver.type'");
  EXPECT_EQ(input_error([&] { top.fail("bad"); }), "scene.yaml:1: bad");  // the root has no path
}

TEST(YamlJoin, ListsNamesWithCommas) {
  EXPECT_EQ(join({}), "");
  EXPECT_EQ(join({"a"}), "a");
  EXPECT_EQ(join({"mesh", "materials", "solver"}), "mesh, materials, solver");
}

}  // namespace
}  // namespace tensormass::scene_yaml
