// `tensormass raise-order`: exit codes, messages, summary and the written file.
#include <gtest/gtest.h>

#include "support/test_support.hpp"

namespace {

using test_support::Result;
using test_support::TempDir;

Result cli(const TempDir& dir, const std::string& command) {
  return test_support::shell_apart("cd '" + dir.path().string() + "' && '" TENSORMASS_BINARY "' " + command);
}

TEST(RaiseOrderCli, MakesHex27FromAHex8Beam) {
  const TempDir dir;
  ASSERT_EQ(cli(dir, "beam --dim 3 --cells 4,2,2 -o hex8.msh").exit_code, 0);
  const Result result = cli(dir, "raise-order hex8.msh --complete -o hex27.msh");
  ASSERT_EQ(result.exit_code, 0) << result.error;
  EXPECT_NE(result.output.find("hex27.msh: 3D, 225 nodes, 16 cells (16 hex27)"), std::string::npos) << result.output;
  const Result info = cli(dir, "mesh-info hex27.msh");
  EXPECT_EQ(info.exit_code, 0) << info.error;
  EXPECT_NE(info.output.find("inverted        0"), std::string::npos) << info.output;
}

TEST(RaiseOrderCli, HelpExitsZero) {
  const TempDir dir;
  const Result result = cli(dir, "raise-order --help");
  EXPECT_EQ(result.exit_code, 0);
  EXPECT_NE(result.output.find("--complete"), std::string::npos);
  EXPECT_TRUE(dir.files().empty());
}

TEST(RaiseOrderCli, BadArgumentsExitTwoWithAMessageAndWriteNothing) {
  const std::vector<std::pair<std::string, std::string>> cases{
      {"raise-order -o out.msh", "missing IN.msh"},
      {"raise-order in.msh", "missing -o"},
      {"raise-order in.msh -o out.msh --frobnicate", "unknown option '--frobnicate'"},
      {"raise-order in.msh -o out.msh --format 3.0", "4.1"},
      {"raise-order in.msh -o out.msh", "in.msh"},
  };
  for (const auto& [args, phrase] : cases) {
    const TempDir dir;
    const Result result = cli(dir, args);
    EXPECT_EQ(result.exit_code, 2) << args;
    EXPECT_NE(result.error.find(phrase), std::string::npos) << args << ": " << result.error;
    EXPECT_TRUE(dir.files().empty()) << args;
  }
}

}  // namespace
