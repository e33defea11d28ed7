// The command line's entry (runtime/cli/main.cpp): help, version, unknown commands.
#include <gtest/gtest.h>

#include "support/test_support.hpp"
#include "tensormass/common/version.hpp"

namespace {

using test_support::Result;

Result cli(const std::string& arguments) { return test_support::shell_apart("'" TENSORMASS_BINARY "' " + arguments); }

TEST(MainCli, VersionPrintsTheProjectVersion) {
  for (const char* spelling : {"--version", "version"}) {
    const Result result = cli(spelling);
    EXPECT_EQ(result.exit_code, 0) << spelling;
    EXPECT_EQ(result.output, std::string("tensormass ") + tensormass::kVersion + "\n") << spelling;
  }
}

TEST(MainCli, HelpListsTheCommandsAndExitsZero) {
  const Result result = cli("help");
  EXPECT_EQ(result.exit_code, 0);
  for (const char* command : {"run SCENE.yaml", "beam", "mesh-info", "raise-order", "--version"})
    EXPECT_NE(result.output.find(command), std::string::npos) << command;
}

TEST(MainCli, UnknownOrMissingCommandExitsTwoWithTheUsage) {
  const Result unknown = cli("frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.error.find("unknown command 'frobnicate'"), std::string::npos) << unknown.error;
  const Result missing = cli("");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.error.find("missing command"), std::string::npos) << missing.error;
}

}  // namespace
