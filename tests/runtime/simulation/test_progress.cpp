// The progress display of a run (progress.cpp): with stderr not a terminal
// it prints a plain line each time the run enters a new tenth, the first
// tenth at its first step (label,
// steps done of total, percent, mean step time), nothing when disabled,
// and finish() adds nothing; a total of 0 counts as 1.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "simulation/progress.hpp"
#include "support/test_support.hpp"

namespace tensormass::detail {
namespace {

using test_support::expect_contains;

/// The lines written to stderr by `run` (gtest redirects stderr to a file,
/// so the Progress made inside sees no terminal).
template <class Run>
std::vector<std::string> stderr_lines(Run run) {
  ::testing::internal::CaptureStderr();
  run();
  const std::string text = ::testing::internal::GetCapturedStderr();
  std::vector<std::string> lines;
  std::size_t start = 0;
  for (std::size_t end; (end = text.find('\n', start)) != std::string::npos; start = end + 1)
    lines.push_back(text.substr(start, end - start));
  if (start < text.size()) lines.push_back(text.substr(start) + "<no line end>");
  return lines;
}

/// The "label done/total" head of each line.
std::vector<std::string> heads(const std::vector<std::string>& lines) {
  std::vector<std::string> result;
  for (const std::string& line : lines) result.push_back(line.substr(0, line.find(" (")));
  return result;
}

TEST(Progress, PlainLinesAtTheFirstStepThenEveryTenPercent) {
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(100, "steps", true);
    for (int done = 1; done <= 100; ++done) progress.update(done, 2.5);
    progress.finish();
  });
  std::vector<std::string> expected{"steps 1/100"};  // the first tenth, 0 %, at its first step
  for (int done = 10; done <= 100; done += 10) expected.push_back("steps " + std::to_string(done) + "/100");
  EXPECT_EQ(heads(lines), expected);
}

TEST(Progress, ALineGivesPercentMeanStepTimeAndElapsed) {
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(4, "load steps", true);
    progress.update(2, 12.5);
  });
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("load steps 2/4 (50%), 12.5 ms/step, ", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(" s elapsed"), std::string::npos) << lines[0];
}

TEST(Progress, FewStepsGiveOneLineEach) {
  // Three steps: 33 %, 66 %, 100 % are three different tenths.
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(3, "steps", true);
    for (int done = 1; done <= 3; ++done) progress.update(done, 1.0);
    progress.finish();
  });
  EXPECT_EQ(heads(lines), (std::vector<std::string>{"steps 1/3", "steps 2/3", "steps 3/3"}));
  ASSERT_EQ(lines.size(), 3u);
  expect_contains(lines[0], {"(33%)"});
  expect_contains(lines[2], {"(100%)"});
}

TEST(Progress, StepsWithinATenthAreNotRepeated) {
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(1000, "steps", true);
    for (int done = 1; done <= 250; ++done) progress.update(done, 1.0);
  });
  EXPECT_EQ(heads(lines), (std::vector<std::string>{"steps 1/1000", "steps 100/1000", "steps 200/1000"}));
}

TEST(Progress, DisabledPrintsNothing) {
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(10, "steps", false);
    for (int done = 1; done <= 10; ++done) progress.update(done, 1.0);
    progress.finish();
  });
  EXPECT_TRUE(lines.empty());
}

TEST(Progress, AZeroTotalCountsAsOneStep) {
  const std::vector<std::string> lines = stderr_lines([] {
    Progress progress(0, "steps", true);
    progress.update(1, 1.0);
  });
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0].rfind("steps 1/1 (100%)", 0), 0u) << lines[0];
}

}  // namespace
}  // namespace tensormass::detail
