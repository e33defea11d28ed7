// `tensormass bench ...` (bench_command.cpp): the CLI runs the separate
// tensormass-bench program found beside it, passing the arguments and the
// exit status through; without that program it exits 2 saying so.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;
using test_support::Result;
using test_support::TempDir;

#ifdef TENSORMASS_WITH_BENCH
TEST(BenchCommand, PaperSmokeRunsThroughTheCli) {
  const Result smoke = test_support::tensormass("bench paper --smoke");
  ASSERT_EQ(smoke.exit_code, 0) << smoke.output;
  EXPECT_NE(smoke.output.find("tensormass bench paper (--smoke)"), std::string::npos) << smoke.output;
  // The benchmark's own exit status and message come back unchanged.
  const Result bad = test_support::tensormass("bench paper --quick --smoke");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("--quick and --smoke exclude each other"), std::string::npos) << bad.output;
}
#endif

TEST(BenchCommand, WithoutTheBenchProgramExitsTwo) {
  if (fs::exists(fs::path(TENSORMASS_INSTALL_BINDIR) / "tensormass-bench"))
    GTEST_SKIP() << "tensormass-bench is installed in " << TENSORMASS_INSTALL_BINDIR;
  const TempDir dir;
  const fs::path alone = dir.path() / "tensormass";  // the CLI copied alone: nothing beside it
  fs::copy_file(TENSORMASS_BINARY, alone);
  const Result result = test_support::shell("'" + alone.string() + "' bench paper --smoke");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("tensormass bench: benchmarks not built (configure with -DTENSORMASS_BUILD_BENCH=ON)"),
            std::string::npos)
      << result.output;
}

}  // namespace
