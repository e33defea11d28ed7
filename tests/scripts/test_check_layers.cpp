// scripts/check_layers.py under /usr/bin/python3: the runtime's folders
// include one another one way only, in the order docs/architecture.md
// states; an include against it is named by file and line.
#include <gtest/gtest.h>

#include <string>

#include "script_test_support.hpp"

namespace {

using script_test::run_script;
using test_support::Result;
using test_support::TempDir;

const char* kArchitecture = "# Architecture\n\nLayers, lowest first: `common < mesh < model`\n";

TEST(CheckLayers, TheSourceTreeRunsOneWay) {
  const Result result = run_script("check_layers.py", "--root '" + test_support::source_path("") + "'");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("all one way"), std::string::npos) << result.output;
}

TEST(CheckLayers, AnIncludeAgainstTheOrderIsNamedByFileAndLine) {
  const TempDir dir;
  dir.write("docs/architecture.md", kArchitecture);
  dir.write("runtime/src/common/vec.hpp", "#pragma once\n");
  dir.write("runtime/src/model/model.cpp", "#include \"tensormass/mesh/mesh.hpp\"\n#include \"common/vec.hpp\"\n");
  dir.write("runtime/include/tensormass/mesh/mesh.hpp",
            "#pragma once\n#include <vector>\n#include \"tensormass/model/model.hpp\"\n");
  const Result result = run_script("check_layers.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("runtime/include/tensormass/mesh/mesh.hpp:3: mesh/ includes "
                               "\"tensormass/model/model.hpp\""),
            std::string::npos)
      << result.output;
  EXPECT_EQ(result.output.find("model.cpp"), std::string::npos) << result.output;  // downward: allowed
}

TEST(CheckLayers, AFolderOutsideTheOrderOrAMissingOrderIsRefused) {
  const TempDir dir;
  dir.write("docs/architecture.md", kArchitecture);
  dir.write("runtime/src/extra/extra.cpp", "\n");
  Result result = run_script("check_layers.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("extra/ is not in the layer order"), std::string::npos) << result.output;
  dir.write("docs/architecture.md", "# Architecture\n");
  result = run_script("check_layers.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("Layers, lowest first"), std::string::npos) << result.output;
}

}  // namespace
