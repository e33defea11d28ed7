// The untimed logic of `tensormass bench paper` (bench/paper_report.hpp):
// the error metric of the origin's Figure 12, the threshold calibration
// helper and the JSON rows, on hand-made data.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "paper_report.hpp"

namespace tensormass::bench {
namespace {

TEST(PaperError, NodalDistanceIsEuclideanPerNode) {
  // Two 2D nodes: displacements differ by (3, 4) at node 1 -> distance 5.
  const std::vector<double> a{0, 0, 1, 1}, b{0, 0, 4, 5};
  EXPECT_DOUBLE_EQ(max_nodal_distance(a, b, 2), 5.0);
  // Read as 1D nodes the same data gives the largest component (4).
  EXPECT_DOUBLE_EQ(max_nodal_distance(a, b, 1), 4.0);
  // 3D: one node.
  const std::vector<double> c{1, 2, 2}, d{0, 0, 0};
  EXPECT_DOUBLE_EQ(max_nodal_distance(c, d, 3), 3.0);
  EXPECT_DOUBLE_EQ(max_nodal_distance(c, c, 3), 0.0);
}

TEST(PaperError, NodalDistanceRejectsMismatchAndKeepsNan) {
  const std::vector<double> a{0, 0, 0, 0}, b{0, 0, 0};
  EXPECT_THROW(max_nodal_distance(a, b, 2), std::invalid_argument);
  EXPECT_THROW(max_nodal_distance(b, b, 2), std::invalid_argument);
  const std::vector<double> nan{0, 0, std::numeric_limits<double>::quiet_NaN(), 0};
  EXPECT_TRUE(std::isnan(max_nodal_distance(nan, a, 2)));
}

TEST(PaperError, TrajectoryErrorIsTheWorstStepOverLength) {
  const Trajectory reference{{0, 0}, {0, 0}, {0, 0}};
  const Trajectory run{{0, 1}, {0, 3}, {0, 2}};  // one 2D node; worst distance 3 at step 2
  EXPECT_DOUBLE_EQ(trajectory_error(run, reference, 2, 6.0), 0.5);
  EXPECT_DOUBLE_EQ(trajectory_error(reference, reference, 2, 6.0), 0.0);
  // A run that stopped early is not comparable.
  const Trajectory shorter{{0, 1}};
  EXPECT_THROW(trajectory_error(shorter, reference, 2, 6.0), std::invalid_argument);
  EXPECT_THROW(trajectory_error(run, reference, 2, 0.0), std::invalid_argument);
}

TEST(PaperError, UpgradeThresholdLeavesTheShareAbove) {
  std::vector<double> values;
  for (int i = 1; i <= 100; ++i) values.push_back(i);
  auto above = [&](double t) {
    int n = 0;
    for (double v : values) n += v > t;
    return n;
  };
  EXPECT_EQ(above(upgrade_threshold(values, 0.5)), 50);
  EXPECT_EQ(above(upgrade_threshold(values, 0.2)), 20);
  EXPECT_EQ(above(upgrade_threshold(values, 0.05)), 5);
  EXPECT_EQ(above(upgrade_threshold(values, 0.001)), 1);  // at least one element
  EXPECT_THROW(upgrade_threshold({}, 0.5), std::invalid_argument);
  EXPECT_THROW(upgrade_threshold(values, 1.0), std::invalid_argument);
}

TEST(PaperStatistics, MedianAndMean) {
  EXPECT_DOUBLE_EQ(median({3, 1, 2}), 2.0);
  EXPECT_DOUBLE_EQ(median({4, 1, 2, 3}), 2.5);
  EXPECT_DOUBLE_EQ(mean({1, 2, 3, 6}), 3.0);
  EXPECT_TRUE(std::isnan(median({})));
}

std::vector<PaperRow> sample_rows() {
  auto row = [](std::string mode, std::optional<double> threshold, double ms, double error, int upgraded) {
    PaperRow r;
    r.beam = "quad 60x10";
    r.elements = 600;
    r.mode = std::move(mode);
    r.threshold = threshold;
    r.ms_per_step = ms;
    r.ms_per_step_median = ms * 0.9;
    r.error = error;
    r.upgraded = upgraded;
    r.samples = {ms, ms * 1.1};
    return r;
  };
  return {row("hooke", std::nullopt, 1.0, 0.04, 0), row("stvk", std::nullopt, 1.2, 0.0, 600),
          row("R_EL", 0.06, 1.05, 0.03, 100),       row("R_EL", 0.015, 1.15, 0.01, 500),
          row("R_EL", 0.03, 1.1, 0.02, 300),        row("R_NL", 0.03, 1.1, 0.015, 400)};
}

TEST(PaperJson, RowsHaveTheSchemaKeys) {
  const Json json = rows_json(sample_rows());
  ASSERT_TRUE(json.is_array());
  ASSERT_EQ(json.size(), sample_rows().size());  // one object per row
  std::vector<std::string> keys;
  for (const auto& item : json[0].items()) keys.push_back(item.key());
  EXPECT_EQ(keys,
            (std::vector<std::string>{"beam", "elements", "mode", "threshold", "ms_per_step", "ms_per_step_median",
                                      "error", "upgraded", "criteria_ms", "assembly_ms", "solve_ms", "samples"}));
  EXPECT_EQ(json[0]["beam"], "quad 60x10");
  EXPECT_EQ(json[0]["mode"], "hooke");
  EXPECT_TRUE(json[0]["elements"].is_number_integer());
  EXPECT_EQ(json[0]["elements"], 600);
  EXPECT_TRUE(json[0]["threshold"].is_null());
  EXPECT_EQ(json[0]["samples"], Json::array({1.0, 1.1}));
  EXPECT_EQ(json[0]["criteria_ms"], 0.0);
  EXPECT_EQ(json[3]["threshold"], 0.015);
  EXPECT_EQ(json[3]["ms_per_step"], 1.15);
  EXPECT_EQ(json[3]["error"], 0.01);
  EXPECT_TRUE(json[3]["upgraded"].is_number_integer());
  EXPECT_EQ(json[3]["upgraded"], 500);
  EXPECT_EQ(rows_json({}), Json::array());
}

TEST(PaperJson, NamesAreEscapedAndNonFiniteNumbersNull) {
  std::vector<PaperRow> rows = sample_rows();
  rows[0].beam = "a\"b\\c\n\x01";
  rows[0].error = std::numeric_limits<double>::quiet_NaN();
  rows[0].samples = {std::numeric_limits<double>::infinity(), 1.5};
  const Json parsed = Json::parse(json_text(rows_json(rows)));
  EXPECT_EQ(parsed[0]["beam"], rows[0].beam);
  EXPECT_TRUE(parsed[0]["error"].is_null());
  EXPECT_TRUE(parsed[0]["samples"][0].is_null());
  EXPECT_EQ(parsed[0]["samples"][1], 1.5);
}

TEST(PaperTable, FindRowByModeAndThreshold) {
  const auto rows = sample_rows();
  ASSERT_NE(find_row(rows, "quad 60x10", "R_EL", 0.03), nullptr);
  EXPECT_EQ(find_row(rows, "quad 60x10", "R_EL", 0.03)->upgraded, 300);
  EXPECT_EQ(find_row(rows, "quad 60x10", "R_V"), nullptr);
  EXPECT_EQ(find_row(rows, "quad 60x10", "stvk")->upgraded, 600);
}

}  // namespace
}  // namespace tensormass::bench
