// scripts/plot_track.py under /usr/bin/python3: a PNG from one or two
// tracks with the max difference printed; exit 2 on missing or malformed
// CSVs and mismatched times (compare_tracks.py too, as it reads them alike).
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "script_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using script_test::run_script;
using script_test::track;
using test_support::Result;
using test_support::TempDir;

TEST(PlotTrack, TwoTracksMakeAPngAndPrintTheMaxDifference) {
  TempDir dir;
  const std::string a = dir.write("a.csv", track(0.010)), b = dir.write("b.csv", track(0.015));
  const Result result = run_script("plot_track.py", a + " " + b + " --label hooke --label stvk -o " +
                                                        dir.file("plot.png") + " --title 'tumour centroid'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ASSERT_TRUE(fs::exists(dir.path() / "plot.png"));
  EXPECT_GT(fs::file_size(dir.path() / "plot.png"), 1000u);
  EXPECT_EQ(test_support::read_file(dir.path() / "plot.png").substr(1, 3), "PNG");
  // max |y_b - y_a| = 0.005 * 0.4 m = 2 mm
  EXPECT_NE(result.output.find("max difference: 2 mm (stvk vs hooke)"), std::string::npos) << result.output;
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(PlotTrack, OneTrackMakesAPngWithoutDifference) {
  TempDir dir;
  const Result result = run_script("plot_track.py", dir.write("a.csv", track(0.01)) + " -o " + dir.file("one.png"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_GT(fs::file_size(dir.path() / "one.png"), 1000u);
  EXPECT_EQ(result.output.find("max difference"), std::string::npos) << result.output;
}

struct BadInput {
  const char* name;
  const char* second;    ///< text of the second CSV ("" = missing file)
  const char* expected;  ///< in the message
};

class PlotTrackBadInput : public ::testing::TestWithParam<BadInput> {};

TEST_P(PlotTrackBadInput, ExitsWithTwoAndWritesNothing) {
  TempDir dir;
  const BadInput bad = GetParam();
  const std::string a = dir.write("a.csv", track(0.01));
  const std::string b = std::string(bad.second).empty() ? dir.file("absent.csv") : dir.write("b.csv", bad.second);
  for (const char* name : {"plot_track.py", "compare_tracks.py"}) {
    const std::string output = std::string(name) == "plot_track.py" ? " -o " + dir.file("plot.png") : "";
    const Result result = run_script(name, a + " " + b + output);
    EXPECT_EQ(result.exit_code, 2) << name << ": " << result.output;
    EXPECT_NE(result.output.find(bad.expected), std::string::npos) << name << ": " << result.output;
    EXPECT_EQ(result.output.find("Traceback"), std::string::npos) << result.output;
  }
  EXPECT_FALSE(fs::exists(dir.path() / "plot.png"));
}

INSTANTIATE_TEST_SUITE_P(
    Files, PlotTrackBadInput,
    ::testing::Values(BadInput{"Missing", "", "absent.csv: cannot read"},
                      BadInput{"NotATrack", "a,b\n1,2\n", "b.csv:1: expected the header"},
                      BadInput{"NotANumber", "time,x,y,z,ux,uy,uz\n0,1,2,0,0,zero,0\n", "b.csv:2: not a number"},
                      BadInput{"ShortRow", "time,x,y,z,ux,uy,uz\n0,1,2,0\n", "b.csv:2: expected 7 values"},
                      BadInput{"NoRows", "time,x,y,z,ux,uy,uz\n", "b.csv: no rows"},
                      BadInput{"FewerRows", "time,x,y,z,ux,uy,uz\n0,1,2,0,0,0,0\n", "the time columns must match"},
                      BadInput{"OtherTimes",
                               "time,x,y,z,ux,uy,uz\n0,1,2,0,0,0,0\n0.1,1,2,0,0,0,0\n0.25,1,2,0,0,0,0\n"
                               "0.3,1,2,0,0,0,0\n0.4,1,2,0,0,0,0\n",
                               "b.csv:4: time 0.25"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(PlotTrack, LabelCountMustMatch) {
  TempDir dir;
  const std::string a = dir.write("a.csv", track(0.01)), b = dir.write("b.csv", track(0.02));
  const Result result = run_script("plot_track.py", a + " " + b + " --label only -o " + dir.file("plot.png"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--label"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir.path() / "plot.png"));
}

}  // namespace
