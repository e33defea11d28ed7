// The key passes over a scene tree (check_keys and apply_override in
// scene/yaml_reader.hpp) against a small key table: unknown and duplicate
// keys named at their line, and "a.b=value" overrides editing the tree,
// creating maps of the schema only, and refused with "--set KEY: why".
// (The same through load_scene with the real schema: test_scene_overrides.cpp.)
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <string>

#include "scene/yaml_reader.hpp"
#include "support/input_error.hpp"
#include "tensormass/common/errors.hpp"

namespace tensormass::scene_yaml {
namespace {

using test_support::input_error;

const KeyTable kTable = {
    {"", {"mesh", "parts", "solver", "output"}},
    {"parts[]", {"name", "young"}},
    {"solver", {"type", "dt", "newton"}},
    {"solver.newton", {"tolerance", "iterations"}},
    {"output", {"directory"}},
};

const char* kTree =
    "mesh: beam.msh\n"           // 1
    "parts:\n"                   // 2
    "  - {name: a, young: 1}\n"  // 3
    "  - name: b\n"              // 4
    "solver:\n"                  // 5
    "  type: static\n";          // 6

/// The tree above as "scene.yaml"; `apply` applies overrides to it, `check` checks its keys.
class YamlKeys : public ::testing::Test {
 protected:
  void apply(const std::string& text) { apply_override(root, text, kTable, source); }
  void check() const { check_keys(Value(source, root, {}), kTable); }
  std::string apply_error(const std::string& text) {
    return input_error([&] { apply(text); });
  }

  YAML::Node root = read_yaml_text(kTree, "scene.yaml");
  Source source{"scene.yaml"};
};

TEST_F(YamlKeys, KnownKeysPass) {
  EXPECT_EQ(input_error([&] { check(); }), "");
}

TEST_F(YamlKeys, AnUnknownKeyIsNamedAtItsLineWithTheKnownOnes) {
  root = read_yaml_text("mesh: m\nsolver:\n  type: static\n  dtt: 1\n", "scene.yaml");
  EXPECT_EQ(input_error([&] { check(); }), "scene.yaml:4: unknown key 'solver.dtt' (known: type, dt, newton)");
}

TEST_F(YamlKeys, KeysOfListItemsAreChecked) {
  root = read_yaml_text("parts:\n  - {name: a}\n  - {name: b, yuong: 2}\n", "scene.yaml");
  EXPECT_EQ(input_error([&] { check(); }), "scene.yaml:3: unknown key 'parts[1].yuong' (known: name, young)");
}

TEST_F(YamlKeys, ADuplicateKeyIsNamedAtItsSecondLine) {
  root = read_yaml_text("mesh: m\nsolver:\n  type: static\n  dt: 1\n  dt: 2\n", "scene.yaml");
  EXPECT_EQ(input_error([&] { check(); }), "scene.yaml:5: duplicate key 'solver.dt'");
}

TEST_F(YamlKeys, AMapWhereTheTableHasNoneIsLeftToTheTypedRead) {
  root = read_yaml_text("mesh: {any: 1, keys: 2}\n", "scene.yaml");
  EXPECT_EQ(input_error([&] { check(); }), "");
}

TEST_F(YamlKeys, AnOverrideReplacesAValueAndIsNamedByItsKey) {
  apply("solver.type=implicit");
  EXPECT_EQ(root["solver"]["type"].as<std::string>(), "implicit");
  const Value type = Value(source, root, {}).child("solver").child("type");
  EXPECT_EQ(type.line(), 0);
  EXPECT_EQ(input_error([&] { type.fail("unknown"); }), "--set solver.type: solver.type: unknown");
  EXPECT_EQ(Value(source, root, {}).child("mesh").line(), 1);  // the rest keeps its lines
}

TEST_F(YamlKeys, AnOverrideValueIsYaml) {
  apply("parts=[{name: c}, {name: d, young: 3}]");
  ASSERT_TRUE(root["parts"].IsSequence());
  EXPECT_EQ(root["parts"].size(), 2u);
  EXPECT_EQ(root["parts"][1]["young"].as<double>(), 3.0);
  apply("  mesh =  other.msh ");  // spaces around the key are trimmed; the value is YAML's to trim
  EXPECT_EQ(root["mesh"].as<std::string>(), "other.msh");
  apply("solver.dt=");  // nothing: a null value
  EXPECT_TRUE(root["solver"]["dt"].IsNull());
}

TEST_F(YamlKeys, ListItemsAreAddressedByIndex) {
  apply("parts.1.young=5");
  EXPECT_EQ(root["parts"][1]["young"].as<int>(), 5);
  EXPECT_EQ(root["parts"][0]["young"].as<int>(), 1);
  apply("parts.0={name: z}");
  EXPECT_EQ(root["parts"][0]["name"].as<std::string>(), "z");
  EXPECT_FALSE(root["parts"][0]["young"].IsDefined());
}

TEST_F(YamlKeys, MissingMapsOfTheSchemaAreCreated) {
  apply("solver.newton.tolerance=1e-8");
  EXPECT_EQ(root["solver"]["newton"]["tolerance"].as<double>(), 1e-8);
  EXPECT_EQ(root["solver"]["type"].as<std::string>(), "static");
  apply("output.directory=out");
  EXPECT_EQ(root["output"]["directory"].as<std::string>(), "out");
  EXPECT_EQ(input_error([&] { check(); }), "");
}

TEST_F(YamlKeys, AMapCreatedByAnOverrideIsNamedByIt) {
  apply("output.directory=out");
  const Value output = Value(source, root, {}).child("output");
  EXPECT_EQ(input_error([&] { output.fail("bad"); }), "--set output.directory: output: bad");
}

TEST_F(YamlKeys, TheLaterOfTwoOverridesWins) {
  apply("solver.dt=1");
  apply("solver.dt=2");
  EXPECT_EQ(root["solver"]["dt"].as<int>(), 2);
}

TEST_F(YamlKeys, MalformedOverridesAreRefused) {
  EXPECT_EQ(apply_error("solver.dt"),
            "--set solver.dt: malformed override: expected key=value (for example solver.dt=0.005)");
  EXPECT_EQ(apply_error(" =3"), "--set  =3: malformed override: no key before '='");
  EXPECT_EQ(apply_error("solver..dt=1"), "--set solver..dt: malformed key path (empty name between dots)");
  EXPECT_EQ(apply_error("solver.=1"), "--set solver.: malformed key path (empty name between dots)");
  const std::string bad_yaml = apply_error("solver.dt=[1, 2");
  EXPECT_EQ(bad_yaml.rfind("--set solver.dt: cannot read the value '[1, 2' as YAML: ", 0), 0u) << bad_yaml;
}

TEST_F(YamlKeys, UnknownKeysOfAnOverrideAreRefusedWithTheKnownOnes) {
  EXPECT_EQ(apply_error("solver.dtt=1"), "--set solver.dtt: unknown key 'solver.dtt' (known: type, dt, newton)");
  EXPECT_EQ(apply_error("colour=red"), "--set colour: unknown key 'colour' (known: mesh, parts, solver, output)");
  EXPECT_EQ(apply_error("parts.0.yuong=1"), "--set parts.0.yuong: unknown key 'parts[0].yuong' (known: name, young)");
}

TEST_F(YamlKeys, ABadListIndexIsRefusedWithTheListsLength) {
  for (const char* index : {"2", "x", "-1", "123456789"})
    EXPECT_EQ(apply_error(std::string("parts.") + index + ".name=q"),
              std::string("--set parts.") + index +
                  ".name: 'parts' is a list of 2 items: expected an index from 0, got '" + index + "'");
}

TEST_F(YamlKeys, AnOverrideCannotGoInsideASingleValue) {
  EXPECT_EQ(apply_error("mesh.name=x"), "--set mesh.name: 'mesh' is a single value, not a map or a list");
  root["solver"]["newton"] = 3;
  EXPECT_EQ(apply_error("solver.newton.tolerance=1"),
            "--set solver.newton.tolerance: 'solver.newton' is a single value, not a map or a list");
}

TEST_F(YamlKeys, AMapWhereTheSchemaHasAValueTakesNoKeys) {
  apply("mesh={file: a.msh}");
  EXPECT_EQ(apply_error("mesh.file=b.msh"), "--set mesh.file: 'mesh' takes a value, not keys");
}

TEST_F(YamlKeys, OnlyMapsOfTheSchemaAreCreated) {
  root.remove("parts");
  EXPECT_EQ(apply_error("parts.0.name=a"),
            "--set parts.0.name: 'parts' is not in the scene: set it whole (--set parts=...)");
}

TEST_F(YamlKeys, AnOverrideValueIsBoundedLikeAScene) {
  const std::string deep = "solver.dt=" + std::string(70, '[') + std::string(70, ']');
  EXPECT_EQ(apply_error(deep), "--set solver.dt:1: maps and lists nest deeper than 64 levels");
}

}  // namespace
}  // namespace tensormass::scene_yaml
