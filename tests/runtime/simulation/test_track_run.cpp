// `tensormass run` with output.track: track_<group>.csv per group (steps + 1
// rows from t = 0), the tracks and the real-time factor in summary.json and
// the text report, tracks kept on a numerical failure (exit 3).
#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "track_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using track_test::Result;
using track_test::TempDir;

class TrackRun : public ::testing::Test {
 protected:
  void SetUp() override {
    const Result beam = track_test::tensormass("beam --dim 2 --cells 20,4 --size 5,1 --mix tri3:0.5,quad4:0.5 -o " +
                                               dir_.file("beam.msh"));
    ASSERT_EQ(beam.exit_code, 0) << beam.output;
  }

  /// Runs a scene made of `body` (everything but output) with `track`.
  Result run(const std::string& body, const std::string& track = "[body, phase_quad4]") {
    const std::string head =
        "mesh: beam.msh\n"
        "materials:\n"
        "  - {region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}\n";
    const std::string scene =
        dir_.write("scene.yaml", head + body + "output: {directory: out, track: " + track + "}\n");
    return track_test::tensormass("run " + scene);
  }
  fs::path out(const std::string& name) const { return dir_.path() / "out" / name; }
  std::string summary() const { return track_test::read_file(out("summary.json")); }

  TempDir dir_;
};

const char* kGravity = "fixed: [clamp]\nloads: {gravity: [0, -9.81]}\n";

TEST_F(TrackRun, ImplicitRunWritesOneRowPerStepFromTimeZero) {
  const Result result = run(std::string(kGravity) + "solver: {type: implicit, dt: 0.01, steps: 6}\n");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* name : {"track_body.csv", "track_phase_quad4.csv"}) {
    const auto lines = track_test::read_lines(out(name));
    ASSERT_EQ(lines.size(), 1u + 6u + 1u) << name;
    EXPECT_EQ(lines[0], "time,x,y,z,ux,uy,uz");
    const std::vector<double> first = track_test::numbers(lines[1]);
    ASSERT_EQ(first.size(), 7u);
    EXPECT_EQ(first[0], 0.0);
    for (int c = 4; c < 7; ++c) EXPECT_EQ(first[c], 0.0) << "first displacement not exactly 0";
    for (std::size_t k = 1; k < lines.size(); ++k) {
      const std::vector<double> row = track_test::numbers(lines[k]);
      EXPECT_NEAR(row[0], 0.01 * static_cast<double>(k - 1), 1e-12);
      for (int c = 0; c < 3; ++c) EXPECT_NEAR(row[1 + c] - first[1 + c], row[4 + c], 1e-14);
    }
    EXPECT_LT(track_test::numbers(lines.back())[5], -1e-4) << "the beam sags under gravity";
  }
  // Rest centroids: the whole box and the quad half.
  EXPECT_NEAR(track_test::numbers(track_test::read_lines(out("track_body.csv"))[1])[1], 2.5, 1e-14);
  EXPECT_NEAR(track_test::numbers(track_test::read_lines(out("track_phase_quad4.csv"))[1])[1], 3.75, 1e-14);
  const auto s = nlohmann::ordered_json::parse(summary());
  EXPECT_EQ(s["tracks"].dump(), R"({"body":"track_body.csv","phase_quad4":"track_phase_quad4.csv"})");
  const auto& files = s["files"];
  ASSERT_GE(files.size(), 3u) << s.dump(2);
  EXPECT_EQ(files[files.size() - 3], "track_body.csv");
  EXPECT_EQ(files[files.size() - 2], "track_phase_quad4.csv");
  EXPECT_EQ(files.back(), "summary.json");
  EXPECT_NE(result.output.find("track_body.csv"), std::string::npos) << result.output;
}

/// The number at `pointer` (a JSON pointer: "/time_per_phase_s/total") of the JSON text (NaN when null).
double json_number(const std::string& json, const std::string& pointer) {
  const nlohmann::json value = nlohmann::json::parse(json).at(nlohmann::json::json_pointer(pointer));
  return value.is_null() ? NAN : value.get<double>();
}

TEST_F(TrackRun, ImplicitSummaryHasTheRealTimeFactor) {
  const Result result = run(std::string(kGravity) + "solver: {type: implicit, dt: 0.01, steps: 6}\n");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const std::string s = summary();
  EXPECT_NEAR(json_number(s, "/simulated_seconds"), 0.06, 1e-15);
  const double loop = json_number(s, "/time_loop_seconds"), factor = json_number(s, "/real_time_factor");
  EXPECT_GT(loop, 0);
  EXPECT_GT(factor, 0);
  EXPECT_NEAR(factor, 0.06 / loop, 1e-9 * factor);
  EXPECT_LE(loop, json_number(s, "/time_per_phase_s/total")) << "the time loop is part of the whole run";
  EXPECT_NE(result.output.find("real-time factor"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("s simulated in"), std::string::npos) << result.output;
}

TEST_F(TrackRun, ExplicitSummaryHasTheRealTimeFactor) {
  const Result result = run(std::string(kGravity) + "solver: {type: explicit, dt: 1.0e-5, steps: 20}\n", "[body]");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NEAR(json_number(summary(), "/simulated_seconds"), 2e-4, 1e-18);
  EXPECT_GT(json_number(summary(), "/real_time_factor"), 0);
  EXPECT_EQ(track_test::read_lines(out("track_body.csv")).size(), 1u + 21u);
}

TEST_F(TrackRun, StaticRunHasOneRowPerLoadStepAndNoRealTimeFactor) {
  const Result result = run(std::string(kGravity) + "solver: {type: static, load_steps: 4}\n", "[body]");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const auto lines = track_test::read_lines(out("track_body.csv"));
  ASSERT_EQ(lines.size(), 1u + 5u);
  for (std::size_t k = 1; k < lines.size(); ++k)
    EXPECT_EQ(track_test::numbers(lines[k])[0], static_cast<double>(k - 1) / 4) << "time = load factor";
  const std::string s = summary();
  const auto json = nlohmann::json::parse(s);
  EXPECT_TRUE(json["real_time_factor"].is_null()) << s;
  EXPECT_TRUE(json["simulated_seconds"].is_null()) << s;
  EXPECT_EQ(result.output.find("real-time factor"), std::string::npos) << result.output;
}

// Every node prescribed to x = 0.125 (y free, no load): a rigid translation.
TEST_F(TrackRun, RigidTranslationMovesTheCentroidByTheTranslation) {
  const Result result =
      run("prescribed: [{region: body, displacement: [0.125, null]}]\n"
          "solver: {type: implicit, dt: 0.01, steps: 3}\n");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* name : {"track_body.csv", "track_phase_quad4.csv"}) {
    const auto lines = track_test::read_lines(out(name));
    ASSERT_EQ(lines.size(), 1u + 4u);
    const std::vector<double> first = track_test::numbers(lines[1]);
    for (std::size_t k = 2; k < lines.size(); ++k) {
      const std::vector<double> row = track_test::numbers(lines[k]);
      EXPECT_EQ(row[4], 0.125) << name;
      EXPECT_NEAR(row[5], 0.0, 1e-15) << name;  // y is free: zero up to the solver's rounding
      EXPECT_EQ(row[6], 0.0);
      EXPECT_EQ(row[1], first[1] + 0.125) << name;
      EXPECT_NEAR(row[2], first[2], 1e-15) << name;
    }
  }
}

TEST_F(TrackRun, NumericalFailureKeepsTheTrackUpToTheLastGoodStep) {
  const Result result = run(std::string(kGravity) + "solver: {type: explicit, dt: 0.01, steps: 400}\n", "[body]");
  ASSERT_EQ(result.exit_code, 3) << result.output;
  const auto lines = track_test::read_lines(out("track_body.csv"));
  ASSERT_GE(lines.size(), 2u);
  EXPECT_EQ(lines[0], "time,x,y,z,ux,uy,uz");
  EXPECT_LT(lines.size(), 1u + 401u);
  for (std::size_t k = 1; k < lines.size(); ++k)
    for (double x : track_test::numbers(lines[k])) EXPECT_TRUE(std::isfinite(x)) << lines[k];
  const std::string s = summary();
  EXPECT_NE(s.find("\"status\": \"failed\""), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(s)["tracks"], nlohmann::json({{"body", "track_body.csv"}})) << s;
  for (const auto& entry : fs::directory_iterator(dir_.path() / "out"))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(TrackRun, NoTrackMeansNoFilesAndAnEmptyMap) {
  const Result result = run(std::string(kGravity) + "solver: {type: static, load_steps: 1}\n", "[]");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(nlohmann::json::parse(summary())["tracks"], nlohmann::json::object());
  for (const auto& entry : fs::directory_iterator(dir_.path() / "out"))
    EXPECT_NE(entry.path().filename().string().rfind("track_", 0), 0u) << entry.path();
}

}  // namespace
