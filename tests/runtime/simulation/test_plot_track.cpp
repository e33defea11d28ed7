// scripts/plot_track.py and scripts/compare_tracks.py under /usr/bin/python3:
// a PNG from two tracks with the max difference printed, the max and RMS
// distances, and exit 2 on missing or malformed CSVs and mismatched times.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "track_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using track_test::Result;
using track_test::TempDir;

std::string script(const char* name) { return std::string(TENSORMASS_SOURCE_DIR) + "/scripts/" + name; }

Result python(const char* name, const std::string& arguments) {
  return track_test::shell("/usr/bin/python3 " + script(name) + " " + arguments);
}

/// A track of 5 rows: centroid (1, 2, 0) + t * (0, -dy, 0) at t = 0 .. 0.4.
std::string track(double dy) {
  std::string text = "time,x,y,z,ux,uy,uz\n";
  char line[200];
  for (int k = 0; k < 5; ++k) {
    const double t = 0.1 * k;
    std::snprintf(line, sizeof line, "%.17g,1,%.17g,0,0,%.17g,0\n", t, 2 - dy * t, -dy * t);
    text += line;
  }
  return text;
}

TEST(PlotTrack, TwoTracksMakeAPngAndPrintTheMaxDifference) {
  TempDir dir;
  const std::string a = dir.write("a.csv", track(0.010)), b = dir.write("b.csv", track(0.015));
  const Result result = python("plot_track.py", a + " " + b + " --label hooke --label stvk -o " + dir.file("plot.png") +
                                                    " --title 'tumour centroid'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  ASSERT_TRUE(fs::exists(dir.path() / "plot.png"));
  EXPECT_GT(fs::file_size(dir.path() / "plot.png"), 1000u);
  EXPECT_EQ(track_test::read(dir.path() / "plot.png").substr(1, 3), "PNG");
  // max |y_b - y_a| = 0.005 * 0.4 m = 2 mm
  EXPECT_NE(result.output.find("max difference: 2 mm (stvk vs hooke)"), std::string::npos) << result.output;
  for (const auto& entry : fs::directory_iterator(dir.path()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST(PlotTrack, OneTrackMakesAPngWithoutDifference) {
  TempDir dir;
  const Result result = python("plot_track.py", dir.write("a.csv", track(0.01)) + " -o " + dir.file("one.png"));
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
    const Result result = python(name, a + " " + b + output);
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
  const Result result = python("plot_track.py", a + " " + b + " --label only -o " + dir.file("plot.png"));
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--label"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(dir.path() / "plot.png"));
}

TEST(CompareTracks, PrintsMaxAndRmsDistanceInMillimetres) {
  TempDir dir;
  const std::string a = dir.write("a.csv", track(0.010)), b = dir.write("b.csv", track(0.015));
  const Result text = python("compare_tracks.py", a + " " + b);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("max distance: 2 mm"), std::string::npos) << text.output;
  // distances 0, 0.5, 1, 1.5, 2 mm: rms = sqrt(7.5 / 5)
  char rms[64];
  std::snprintf(rms, sizeof rms, "rms distance: %.6g mm", std::sqrt(1.5));
  EXPECT_NE(text.output.find(rms), std::string::npos) << text.output;
  const Result json = python("compare_tracks.py", a + " " + b + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const std::string check = "/usr/bin/python3 -c \"import json,sys; d=json.loads(sys.argv[1]); "
                            "assert abs(d['max_mm']-2)<1e-9 and abs(d['rms_mm']-1.5**0.5)<1e-9 and d['samples']==5\" '" +
                            json.output + "'";
  EXPECT_EQ(std::system(check.c_str()), 0) << json.output;
}

TEST(CompareTracks, DisplacementIgnoresTheRestCentroid) {
  TempDir dir;
  std::string shifted = track(0.01);
  for (std::size_t at = shifted.find(",1,"); at != std::string::npos; at = shifted.find(",1,", at + 3))
    shifted.replace(at, 3, ",1.5,");
  const std::string a = dir.write("a.csv", track(0.01)), b = dir.write("b.csv", shifted);
  EXPECT_NE(python("compare_tracks.py", a + " " + b).output.find("max distance: 500 mm"), std::string::npos);
  EXPECT_NE(python("compare_tracks.py", a + " " + b + " --displacement").output.find("max distance: 0 mm"),
            std::string::npos);
}

}  // namespace
