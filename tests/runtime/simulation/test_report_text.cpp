// The terminal summary of a run (report_text.cpp): format_report on a
// report built by hand gives the scene and mesh, the cells per type and
// law, the solver line of each kind of solve, the mean and median step
// time, the Newton iterations per step, the adaptivity switches (at most
// six steps listed), the real-time factor, the warnings and the files written.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "report_test_support.hpp"
#include "support/test_support.hpp"
#include "tensormass/simulation/simulation.hpp"

namespace tensormass {
namespace {

using test_support::expect_contains;

class ReportText : public ::testing::Test {
 protected:
  ReportText() : scene_(test::report_scene()), report_(test::report_of_four_steps()) {}

  std::string text() const { return format_report(scene_, report_); }

  Scene scene_;
  RunReport report_;
};

TEST_F(ReportText, NamesTheSceneMeshCellsAndLaws) {
  const std::string t = text();
  EXPECT_EQ(t.rfind("tensormass run scenes/beam.yaml\n", 0), 0u) << t;
  expect_contains(
      t, {"  mesh      meshes/beam.msh: 8 quad4; 15 nodes, 30 dofs (24 free)\n", "  laws      6 stvk, 2 hooke\n"});
}

TEST_F(ReportText, GivesTheMeanAndMedianStepTime) {
  expect_contains(text(), {"  time      2.000 s; per step mean 4.5 ms, median 3.5 ms\n"});
  report_.statistics.step_ms = {7.0, 1.0, 1.0};
  expect_contains(text(), {"per step mean 3 ms, median 1 ms\n"});
}

TEST_F(ReportText, GivesThePhaseTimes) {
  expect_contains(text(), {"  phases    assembly 0.250 s, solve 0.500 s, criteria 0.000 s, output 0.125 s\n"});
}

TEST_F(ReportText, AStaticSolveGivesLoadStepsAndNewtonIterationsPerStep) {
  const std::string t = text();
  expect_contains(t, {"  solver    static, 4 load steps, tolerance 1e-08, linear: cholmod\n",
                      "  newton    9 iterations (2.25 per step); linear iterations 0, factorisations 9\n"});
  EXPECT_EQ(t.find("speed"), std::string::npos) << t;
  EXPECT_EQ(t.find("stable dt"), std::string::npos) << t;
  EXPECT_EQ(t.find("MPI"), std::string::npos) << t;
}

TEST_F(ReportText, ShortenedStepsAndRanksAreNamedWhenThereAreAny) {
  report_.statistics.shortened_steps = 2;
  report_.statistics.linear_iterations = 40;
  report_.statistics.factorizations = 0;
  report_.mpi_ranks = 3;
  const std::string t = text();
  expect_contains(t,
                  {"linear: cholmod on 3 MPI ranks\n",
                   "  newton    9 iterations (2.25 per step), 2 shortened by the line search; linear iterations 40\n"});
  EXPECT_EQ(t.find("factorisations"), std::string::npos) << t;
}

TEST_F(ReportText, AnExplicitSolveGivesDtStableDtAndRealTimeFactorButNoNewton) {
  scene_.solver.type = SolverType::explicit_euler;
  scene_.solver.dt = 1e-4;
  scene_.solver.steps = 100;
  report_.statistics.stable_dt = 2e-4;
  report_.simulated_seconds = 0.01;
  report_.loop_seconds = 0.04;
  const std::string t = text();
  expect_contains(
      t, {"  solver    explicit, dt 0.0001 s, 100 steps, linear: cholmod\n", "  stable dt 0.0002 s (estimated)\n",
          "  speed     real-time factor 0.25 (0.01 s simulated in 0.04 s)\n"});
  EXPECT_EQ(t.find("newton"), std::string::npos) << t;
}

TEST_F(ReportText, AnImplicitSolveGivesNewtonAndSpeedButNoStableDt) {
  scene_.solver.type = SolverType::implicit_euler;
  scene_.solver.dt = 0.01;
  scene_.solver.steps = 4;
  report_.simulated_seconds = 0.04;
  report_.loop_seconds = 0.02;
  const std::string t = text();
  expect_contains(t, {"  solver    implicit, dt 0.01 s, 4 steps", "  newton    9 iterations (2.25 per step)",
                      "real-time factor 2 (0.04 s simulated in 0.02 s)"});
  EXPECT_EQ(t.find("stable dt"), std::string::npos) << t;
}

TEST_F(ReportText, ListsTheResultWarningsAndFilesWritten) {
  report_.statistics.warnings = {"cell 3 is nearly inverted", "tolerance not reached at load step 2"};
  const std::string t = text();
  expect_contains(t, {"  result    max displacement 0.75 at node 14\n", "  warning   cell 3 is nearly inverted\n",
                      "  warning   tolerance not reached at load step 2\n",
                      "  output    out/ : final.vtu series.pvd summary.json\n"});
  EXPECT_EQ(t.back(), '\n');
}

TEST_F(ReportText, AdaptivityGivesCriteriaSwitchesAndTheStepsThatSwitched) {
  scene_.adaptivity.enabled = true;
  scene_.adaptivity.criteria = {{"R_EL", 0.1, 0, ""}, {"R_V", 0.2, 0, ""}};
  report_.switches = 5;
  report_.criteria_seconds = 0.5;
  for (const AdaptivityRecord& r : {AdaptivityRecord{1, 0, 0, {}}, {2, 3, 0, {}}, {3, 1, 1, {}}})
    report_.adaptivity.add(r);
  const std::string t = text();
  expect_contains(
      t, {"  adapt     R_EL 0.1, R_V 0.2: 5 switches, criteria 0.500 s\n", "  switched  step 2 +3, step 3 +1 -1\n"});
  EXPECT_EQ(t.find("step 1 "), std::string::npos) << t;
}

TEST_F(ReportText, AdaptivityListsSixSwitchingStepsAndCountsTheRest) {
  scene_.adaptivity.enabled = true;
  scene_.adaptivity.criteria = {{"R_EL", 0.1, 0, ""}};
  for (int step = 1; step <= 9; ++step) report_.adaptivity.add({step, 1, 0, {}});
  expect_contains(text(),
                  {"  switched  step 1 +1, step 2 +1, step 3 +1, step 4 +1, step 5 +1, step 6 +1 and 3 more\n"});
}

TEST_F(ReportText, NoSwitchedLineWhenNothingSwitched) {
  scene_.adaptivity.enabled = true;
  scene_.adaptivity.criteria = {{"R_EL", 0.1, 0, ""}};
  report_.adaptivity.add({1, 0, 0, {}});
  report_.adaptivity.add({2, 0, 0, {}});
  const std::string t = text();
  expect_contains(t, {"  adapt     R_EL 0.1: 0 switches"});
  EXPECT_EQ(t.find("switched"), std::string::npos) << t;
}

}  // namespace
}  // namespace tensormass
