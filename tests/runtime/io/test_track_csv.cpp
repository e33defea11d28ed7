// The track file's format: its name from the group's, its header, and rows
// of 17 significant digits that read back bit for bit.
// (Tracks written by runs: tests/runtime/simulation/test_track_run.cpp.)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include "tensormass/io/track_csv.hpp"

namespace {

using tensormass::track_csv_header;
using tensormass::track_csv_row;
using tensormass::track_file_name;
using tensormass::TrackRow;

TEST(TrackCsv, FileNameKeepsPlainCharactersAndReplacesTheRest) {
  EXPECT_EQ(track_file_name("tumour"), "track_tumour.csv");
  EXPECT_EQ(track_file_name("left-lobe_2.a"), "track_left-lobe_2.a.csv");
  EXPECT_EQ(track_file_name("a b/c\\d:é"), "track_a_b_c_d___.csv");  // é is two bytes
  EXPECT_EQ(track_file_name("../up"), "track_.._up.csv");
}

TEST(TrackCsv, HeaderNamesTheSevenColumns) { EXPECT_EQ(track_csv_header(), "time,x,y,z,ux,uy,uz\n"); }

TEST(TrackCsv, RowReadsBackBitForBit) {
  const TrackRow row{0.1, {1.0 / 3.0, -2.5e-300, 6.02e23}, {0.0, -0.0, std::nextafter(1.0, 2.0)}};
  const std::string line = track_csv_row(row);
  ASSERT_EQ(line.back(), '\n');
  const char* at = line.c_str();
  double values[7];
  for (double& v : values) {
    char* end = nullptr;
    v = std::strtod(at, &end);
    ASSERT_NE(end, at) << line;
    at = *end == ',' ? end + 1 : end;
  }
  EXPECT_EQ(*at, '\n');
  EXPECT_EQ(values[0], row.time);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(values[1 + c], row.position[c]);
    EXPECT_EQ(values[4 + c], row.displacement[c]);
  }
  EXPECT_TRUE(std::signbit(values[5]));  // -0 stays -0
}

TEST(TrackCsv, TheLongestNumbersFitTheRow) {
  const double big = -std::numeric_limits<double>::max(), tiny = -std::numeric_limits<double>::denorm_min();
  const std::string line = track_csv_row({big, {tiny, big, tiny}, {big, tiny, big}});
  EXPECT_EQ(std::count(line.begin(), line.end(), ','), 6);
  EXPECT_EQ(line.back(), '\n');
}

}  // namespace
