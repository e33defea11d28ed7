// summary.json (summary_json.cpp): write_summary on a report built by hand
// writes the status (with the error of a failed run), the version, the
// steps and their mean and median time, the cells per law and type, the
// law ids of the model, the solver's settings by kind of solve, non-finite
// numbers as null, and the adaptivity and refinement sections only when on;
// mean_and_median on its own.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "report_test_support.hpp"
#include "simulation/summary_json.hpp"
#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/version.hpp"
#include "tensormass/model/model.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

using nlohmann::json;

class SummaryJson : public ::testing::Test {
 protected:
  SummaryJson()
      : mesh_(test::beam(2, "quad4", {4, 2, 1})),
        scene_(test::report_scene()),
        model_(std::make_unique<Model>(mesh_, scene_.model)),
        report_(test::report_of_four_steps()) {}

  /// write_summary's file, parsed.
  json summary(const std::string& failure = "") const {
    const std::string path = dir_.file("summary.json");
    detail::write_summary(path, scene_, *model_, report_, failure);
    return json::parse(test_support::read_file(path));
  }

  test_support::TempDir dir_;
  Mesh mesh_;
  Scene scene_;
  std::unique_ptr<Model> model_;
  RunReport report_;
};

TEST(MeanAndMedian, AnOddCountTakesTheMiddleValue) {
  const auto [mean, median] = detail::mean_and_median({5.0, 1.0, 3.0});
  EXPECT_DOUBLE_EQ(mean, 3.0);
  EXPECT_DOUBLE_EQ(median, 3.0);
  const auto [skewed_mean, skewed_median] = detail::mean_and_median({1.0, 100.0, 2.0});
  EXPECT_DOUBLE_EQ(skewed_mean, 103.0 / 3);
  EXPECT_DOUBLE_EQ(skewed_median, 2.0);
}

TEST(MeanAndMedian, AnEvenCountAveragesTheTwoMiddleValues) {
  const auto [mean, median] = detail::mean_and_median({4.0, 1.0, 3.0, 10.0});
  EXPECT_DOUBLE_EQ(mean, 4.5);
  EXPECT_DOUBLE_EQ(median, 3.5);
}

TEST(MeanAndMedian, NoValuesGiveZeros) {
  const auto [mean, median] = detail::mean_and_median({});
  EXPECT_EQ(mean, 0.0);
  EXPECT_EQ(median, 0.0);
}

TEST_F(SummaryJson, ASuccessfulRunHasStatusOkAndNoError) {
  const json j = summary();
  EXPECT_EQ(j.at("status"), "ok");
  EXPECT_FALSE(j.contains("error"));
  EXPECT_EQ(j.at("version"), std::string(kVersion));
  EXPECT_EQ(j.at("scene"), "scenes/beam.yaml");
  EXPECT_EQ(j.at("mesh"), "meshes/beam.msh");
}

TEST_F(SummaryJson, AFailedRunHasStatusFailedAndItsError) {
  const json j = summary("step 3: the Newton iteration diverged");
  EXPECT_EQ(j.at("status"), "failed");
  EXPECT_EQ(j.at("error"), "step 3: the Newton iteration diverged");
}

TEST_F(SummaryJson, TheStatusAndErrorComeFirst) {
  const std::string path = dir_.file("summary.json");
  detail::write_summary(path, scene_, *model_, report_, "broken");
  const std::string text = test_support::read_file(path);
  EXPECT_LT(text.find("\"status\""), text.find("\"error\""));
  EXPECT_LT(text.find("\"error\""), text.find("\"version\""));
  EXPECT_EQ(text.back(), '\n');
}

TEST_F(SummaryJson, StepsAndTimePerStepAreTheStepTimesCountMeanAndMedian) {
  const json j = summary();
  EXPECT_EQ(j.at("steps"), 4);
  EXPECT_DOUBLE_EQ(j.at("time_per_step_ms").at("mean").get<double>(), 4.5);
  EXPECT_DOUBLE_EQ(j.at("time_per_step_ms").at("median").get<double>(), 3.5);
  EXPECT_EQ(j.at("per_step_ms").at("total"), json({4.0, 1.0, 3.0, 10.0}));
}

TEST_F(SummaryJson, NoStepsGiveZeroMeanAndMedian) {
  report_.statistics.step_ms.clear();
  const json j = summary();
  EXPECT_EQ(j.at("steps"), 0);
  EXPECT_EQ(j.at("time_per_step_ms").at("mean").get<double>(), 0.0);
  EXPECT_EQ(j.at("time_per_step_ms").at("median").get<double>(), 0.0);
}

TEST_F(SummaryJson, CellsPerLawAndTypeKeepTheReportsOrderAndCounts) {
  const std::string path = dir_.file("summary.json");
  detail::write_summary(path, scene_, *model_, report_, "");
  const nlohmann::ordered_json j = nlohmann::ordered_json::parse(test_support::read_file(path));
  const nlohmann::ordered_json& laws = j.at("elements_per_law");
  ASSERT_EQ(laws.size(), 2u);
  EXPECT_EQ(laws.begin().key(), "stvk");
  EXPECT_EQ(laws.at("stvk"), 6);
  EXPECT_EQ(laws.at("hooke"), 2);
  EXPECT_EQ(j.at("elements_per_type"), nlohmann::ordered_json({{"quad4", 8}}));
}

TEST_F(SummaryJson, SizesNewtonCountsAndResultAreTheReports) {
  const json j = summary();
  EXPECT_EQ(j.at("nodes"), 15);
  EXPECT_EQ(j.at("elements"), 8);
  EXPECT_EQ(j.at("dofs"), 30);
  EXPECT_EQ(j.at("free_dofs"), 24);
  EXPECT_EQ(j.at("mpi_ranks"), 1);
  EXPECT_EQ(j.at("newton_iterations").at("total"), 9);
  EXPECT_EQ(j.at("newton_iterations").at("per_step"), json({3, 2, 2, 2}));
  EXPECT_EQ(j.at("newton_iterations").at("shortened_by_line_search"), 0);
  EXPECT_EQ(j.at("factorizations"), 9);
  EXPECT_EQ(j.at("max_displacement").at("value"), 0.75);
  EXPECT_EQ(j.at("max_displacement").at("node"), 14);
  EXPECT_EQ(j.at("files"), json({"final.vtu", "series.pvd", "summary.json"}));
  EXPECT_FALSE(j.contains("resumed_from_step"));
}

TEST_F(SummaryJson, PhaseTimesPutTheRestOfTheWallTimeUnderOther) {
  const json j = summary();
  const json& phases = j.at("time_per_phase_s");
  EXPECT_EQ(phases.at("assembly"), 0.25);
  EXPECT_EQ(phases.at("solve"), 0.5);
  EXPECT_EQ(phases.at("output"), 0.125);
  EXPECT_EQ(phases.at("criteria"), 0.0);
  EXPECT_DOUBLE_EQ(phases.at("other").get<double>(), 2.0 - 0.25 - 0.5 - 0.125);
  EXPECT_EQ(phases.at("total"), 2.0);
  report_.wall_seconds = 0.5;  // less than the phases: other is not negative
  EXPECT_EQ(summary().at("time_per_phase_s").at("other"), 0.0);
}

TEST_F(SummaryJson, LawIdsNumberTheModelsLaws) {
  const json j = summary();
  const std::vector<std::string>& names = model_->law_names();
  ASSERT_FALSE(names.empty());
  ASSERT_EQ(j.at("law_ids").size(), names.size());
  for (std::size_t i = 0; i < names.size(); ++i) EXPECT_EQ(j.at("law_ids").at(std::to_string(i)), names[i]);
}

TEST_F(SummaryJson, AStaticSolveHasLoadStepsAndNoRealTime) {
  const json j = summary();
  const json& solver = j.at("solver");
  EXPECT_EQ(solver.at("type"), "static");
  EXPECT_EQ(solver.at("linear"), "cholmod");
  EXPECT_EQ(solver.at("load_steps"), 4);
  EXPECT_EQ(solver.at("tolerance"), 1e-8);
  EXPECT_FALSE(solver.contains("dt"));
  EXPECT_EQ(solver.at("project_hessian"), false);
  EXPECT_GE(solver.at("threads").get<int>(), 1);
  EXPECT_TRUE(j.at("simulated_seconds").is_null());
  EXPECT_TRUE(j.at("real_time_factor").is_null());
  EXPECT_FALSE(j.contains("stable_dt_s"));
}

TEST_F(SummaryJson, AnExplicitSolveHasDtRealTimeFactorAndStableDt) {
  scene_.solver.type = SolverType::explicit_euler;
  scene_.solver.dt = 1e-4;
  scene_.solver.steps = 100;
  report_.statistics.stable_dt = 2e-4;
  report_.simulated_seconds = 0.01;
  report_.loop_seconds = 0.04;
  const json j = summary();
  const json& solver = j.at("solver");
  EXPECT_EQ(solver.at("type"), "explicit");
  EXPECT_EQ(solver.at("dt"), 1e-4);
  EXPECT_EQ(solver.at("predictor"), "velocity");
  EXPECT_FALSE(solver.contains("load_steps"));
  EXPECT_EQ(j.at("simulated_seconds"), 0.01);
  EXPECT_EQ(j.at("time_loop_seconds"), 0.04);
  EXPECT_DOUBLE_EQ(j.at("real_time_factor").get<double>(), 0.25);
  EXPECT_EQ(j.at("stable_dt_s"), 2e-4);
}

TEST_F(SummaryJson, NonFiniteNumbersAreNull) {
  report_.max_displacement = std::numeric_limits<double>::quiet_NaN();
  report_.statistics.step_ms = {1.0, std::numeric_limits<double>::infinity()};
  const json j = summary();
  EXPECT_TRUE(j.at("max_displacement").at("value").is_null());
  EXPECT_TRUE(j.at("per_step_ms").at("total").at(1).is_null());
  EXPECT_EQ(j.at("per_step_ms").at("total").at(0), 1.0);
  EXPECT_TRUE(j.at("time_per_step_ms").at("mean").is_null());
}

TEST_F(SummaryJson, AResumedRunNamesItsCheckpointStep) {
  report_.resumed_from_step = 2;
  EXPECT_EQ(summary().at("resumed_from_step"), 2);
}

TEST_F(SummaryJson, AdaptivityAndRefinementAppearOnlyWhenOn) {
  json j = summary();
  EXPECT_FALSE(j.contains("adaptivity"));
  EXPECT_FALSE(j.contains("refinement"));

  scene_.adaptivity.enabled = true;
  scene_.adaptivity.criteria = {{"R_EL", 0.1, 0, ""}, {"R_V", 0.2, 0, ""}};
  report_.criterion_seconds = {0.5};  // the second criterion has no time: 0
  report_.adaptivity.add({0, 0, 0, {{"hooke", 8}}});
  report_.adaptivity.add({3, 2, 1, {{"hooke", 1}, {"stvk", 7}}});
  scene_.refinement.enabled = true;
  scene_.refinement.threshold = 0.6;
  scene_.refinement.max_level = 3;
  report_.refinement = {{0, 8, {8}}, {2, 14, {6, 8}}};
  j = summary();
  const json& criteria = j.at("adaptivity").at("criteria");
  ASSERT_EQ(criteria.size(), 2u);
  EXPECT_EQ(criteria[0], json({{"name", "R_EL"}, {"threshold", 0.1}, {"seconds", 0.5}}));
  EXPECT_EQ(criteria[1], json({{"name", "R_V"}, {"threshold", 0.2}, {"seconds", 0.0}}));
  EXPECT_EQ(j.at("adaptivity").at("evaluations"), 2);
  EXPECT_EQ(j.at("adaptivity").at("switching_evaluations"), 1);
  EXPECT_EQ(j.at("adaptivity").at("records"), "adaptivity.jsonl");
  const json& per_step = j.at("adaptivity").at("per_step");
  ASSERT_EQ(per_step.size(), 2u);
  EXPECT_EQ(per_step[1].at("step"), 3);
  EXPECT_EQ(per_step[1].at("upgrades"), 2);
  EXPECT_EQ(per_step[1].at("downgrades"), 1);
  EXPECT_EQ(per_step[1].at("elements_per_law"), json({{"hooke", 1}, {"stvk", 7}}));
  // A record file's line is the same object.
  EXPECT_EQ(json::parse(detail::adaptivity_record_line(report_.adaptivity.listed[1])), per_step[1]);
  const json& refinement = j.at("refinement");
  EXPECT_EQ(refinement.at("criterion"), "R_ZZ");
  EXPECT_EQ(refinement.at("threshold"), 0.6);
  EXPECT_EQ(refinement.at("max_level"), 3);
  ASSERT_EQ(refinement.at("events").size(), 2u);
  EXPECT_EQ(refinement.at("events")[1], json({{"step", 2}, {"cells", 14}, {"leaves_per_level", {6, 8}}}));
}

TEST_F(SummaryJson, TracksMapGroupsToTheirFiles) {
  report_.tracks = {{"tip", "track_tip.csv"}, {"clamp", "track_clamp.csv"}};
  EXPECT_EQ(summary().at("tracks"), json({{"tip", "track_tip.csv"}, {"clamp", "track_clamp.csv"}}));
}

TEST_F(SummaryJson, InvalidUtf8InANameIsReplacedNotThrown) {
  scene_.mesh = "mesh\xff.msh";
  const json j = summary();
  EXPECT_EQ(j.at("mesh"), "mesh\xEF\xBF\xBD.msh");
}

}  // namespace
}  // namespace tensormass
