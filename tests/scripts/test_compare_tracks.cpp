// scripts/compare_tracks.py under /usr/bin/python3: the max and RMS
// distances of two tracks in millimetres (text and JSON), and the
// displacement-only comparison. Its bad-input cases are in test_plot_track.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "script_test_support.hpp"

namespace {

using script_test::run_script;
using script_test::track;
using test_support::Result;
using test_support::TempDir;

TEST(CompareTracks, PrintsMaxAndRmsDistanceInMillimetres) {
  TempDir dir;
  const std::string a = dir.write("a.csv", track(0.010)), b = dir.write("b.csv", track(0.015));
  const Result text = run_script("compare_tracks.py", a + " " + b);
  ASSERT_EQ(text.exit_code, 0) << text.output;
  EXPECT_NE(text.output.find("max distance: 2 mm"), std::string::npos) << text.output;
  // distances 0, 0.5, 1, 1.5, 2 mm: rms = sqrt(7.5 / 5)
  char rms[64];
  std::snprintf(rms, sizeof rms, "rms distance: %.6g mm", std::sqrt(1.5));
  EXPECT_NE(text.output.find(rms), std::string::npos) << text.output;
  const Result json = run_script("compare_tracks.py", a + " " + b + " --json");
  ASSERT_EQ(json.exit_code, 0) << json.output;
  const Result check = test_support::python(
      "-c \"import json,sys; d=json.loads(sys.argv[1]); "
      "assert abs(d['max_mm']-2)<1e-9 and abs(d['rms_mm']-1.5**0.5)<1e-9 and d['samples']==5\" '" +
      json.output + "'");
  EXPECT_EQ(check.exit_code, 0) << json.output << check.output;
}

TEST(CompareTracks, DisplacementIgnoresTheRestCentroid) {
  TempDir dir;
  std::string shifted = track(0.01);
  for (std::size_t at = shifted.find(",1,"); at != std::string::npos; at = shifted.find(",1,", at + 3))
    shifted.replace(at, 3, ",1.5,");
  const std::string a = dir.write("a.csv", track(0.01)), b = dir.write("b.csv", shifted);
  EXPECT_NE(run_script("compare_tracks.py", a + " " + b).output.find("max distance: 500 mm"), std::string::npos);
  EXPECT_NE(run_script("compare_tracks.py", a + " " + b + " --displacement").output.find("max distance: 0 mm"),
            std::string::npos);
}

}  // namespace
