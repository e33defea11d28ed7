// scripts/check_quoted_figures.py under /usr/bin/python3: every figure of the
// README's headline table is on the results page its row links to.
#include <gtest/gtest.h>

#include <string>

#include "script_test_support.hpp"

namespace {

using script_test::run_script;
using test_support::Result;
using test_support::TempDir;

const char* kReadme =
    "# x\n\n## Headline figures\n\n| what | measured | page |\n|---|---|---|\n"
    "| a beam | 5.93x faster, agreement 7.9e-8 | [runtime](docs/results/runtime.md) |\n"
    "| a soak | flat at 150.2 MiB, 0.35 % error | [soak](docs/results/soak.md) |\n\n## Features\n\n| 99 | 98 |\n";

TEST(QuotedFigures, EveryHeadlineFigureOfTheReadmeIsOnItsPage) {
  const Result result = run_script("check_quoted_figures.py", "--root '" + test_support::source_path("") + "'");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("is on its page"), std::string::npos) << result.output;
}

TEST(QuotedFigures, AFigureMissingFromItsPageIsNamedByLine) {
  const TempDir dir;
  dir.write("README.md", kReadme);
  dir.write("docs/results/runtime.md", "| ratio | **5.93x** | 7.9e-8 |\n");
  dir.write("docs/results/soak.md", "150.2 MiB; an error of 0.35 (not a percentage), 2.150.2\n");
  const Result result = run_script("check_quoted_figures.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_EQ(result.output, "README.md:8: 0.35 % is not on docs/results/soak.md\n");
}

TEST(QuotedFigures, AFigureOnlyInsideAnotherNumberIsMissing) {
  const TempDir dir;
  dir.write("README.md", kReadme);
  dir.write("docs/results/runtime.md", "15.93x and 7.9e-80\n");
  dir.write("docs/results/soak.md", "150.2 MiB, 0.35 %\n");
  const Result result = run_script("check_quoted_figures.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("README.md:7: 5.93 is not on docs/results/runtime.md"), std::string::npos)
      << result.output;
  EXPECT_NE(result.output.find("README.md:7: 7.9e-8 is not on"), std::string::npos) << result.output;
}

TEST(QuotedFigures, AMissingPageOrTableIsAnError) {
  const TempDir dir;
  dir.write("README.md", kReadme);
  dir.write("docs/results/soak.md", "150.2 MiB, 0.35 %\n");
  Result result = run_script("check_quoted_figures.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("README.md:7: cannot read docs/results/runtime.md"), std::string::npos) << result.output;
  dir.write("README.md", "# x\n\nno table\n");
  result = run_script("check_quoted_figures.py", "--root '" + dir.path().string() + "'");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("no headline table"), std::string::npos) << result.output;
}

}  // namespace
