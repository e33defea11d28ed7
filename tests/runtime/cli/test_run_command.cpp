// `tensormass run` end to end through the binary: outputs, exit codes 0, 2
// and 3, nothing written on bad input, last_good.vtu on a numerical failure.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code;
  std::string output;  ///< stdout and stderr
};

Result run(const std::string& arguments) {
  const std::string command = std::string(TENSORMASS_BINARY) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

std::string read(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

class RunCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("tensormass-run-" + std::to_string(getpid()) + "-" +
                                              ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(directory_);
    fs::create_directories(directory_);
    const Result beam = run("beam --dim 2 --cells 20,4 --size 5,1 -o " + (directory_ / "beam.msh").string());
    ASSERT_EQ(beam.exit_code, 0) << beam.output;
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path write_scene(const std::string& solver, const std::string& extra = "") {
    const fs::path path = directory_ / "scene.yaml";
    std::ofstream(path) << "mesh: beam.msh\n"
                           "materials:\n"
                           "  - {region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}\n"
                           "fixed: [clamp]\n"
                           "loads:\n"
                           "  gravity: [0, -9.81, 0]\n"
                           "solver:\n"
                        << solver << "output: {directory: out, every: 2}\n"
                        << extra;
    return path;
  }
  fs::path out() const { return directory_ / "out"; }

  fs::path directory_;
};

const char* kStatic = "  type: static\n  load_steps: 4\n  tolerance: 1.0e-10\n";
const char* kImplicit = "  type: implicit\n  dt: 0.01\n  steps: 6\n  newton_iterations: 2\n";

TEST_F(RunCommand, StaticSceneWritesFinalFramesSeriesAndSummary) {
  const Result result = run("run " + write_scene(kStatic).string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* name : {"final.vtu", "frame_000002.vtu", "frame_000004.vtu", "series.pvd", "summary.json"})
    EXPECT_TRUE(fs::exists(out() / name)) << name;
  const std::string summary = read(out() / "summary.json");
  for (const char* key : {"\"status\": \"ok\"", "\"steps\": 4", "\"time_per_step_ms\"", "\"time_per_phase_s\"",
                          "\"newton_iterations\"", "\"linear_iterations\"", "\"elements_per_law\": {\"stvk\": 80}",
                          "\"switches\"", "\"law_ids\""})
    EXPECT_NE(summary.find(key), std::string::npos) << key << "\n" << summary;
  EXPECT_NE(result.output.find("max displacement"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(out()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

TEST_F(RunCommand, FinalVtuOpensInMeshioWithThreeComponentDisplacement) {
  ASSERT_EQ(run("run --quiet " + write_scene(kImplicit).string()).exit_code, 0);
  const std::string check = "/usr/bin/python3 -c \"import meshio,sys; m=meshio.read(sys.argv[1]); "
                            "d=m.point_data['displacement']; assert d.shape==(len(m.points),3); "
                            "assert 'law_id' in m.cell_data and 'element_type' in m.cell_data; "
                            "assert abs(d[:,1]).max()>0\" " + (out() / "final.vtu").string();
  EXPECT_EQ(std::system(check.c_str()), 0);
}

TEST_F(RunCommand, SetOverridesAKey) {
  const Result result = run("run " + write_scene(kImplicit).string() + " --set solver.steps=2 --set output.every=0");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(read(out() / "summary.json").find("\"steps\": 2"), std::string::npos);
  EXPECT_FALSE(fs::exists(out() / "series.pvd"));
}

TEST_F(RunCommand, ProgressIsPlainLinesWhenNotATerminal) {
  const Result result = run("run " + write_scene(kImplicit).string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("implicit 6/6 (100%)"), std::string::npos) << result.output;
  EXPECT_EQ(result.output.find('\r'), std::string::npos);
}

struct BadScene {
  const char* name;
  const char* extra_or_solver;  ///< replaces the solver block
  const char* expected;          ///< in the one-line message
};

class RunCommandBadInput : public RunCommand, public ::testing::WithParamInterface<BadScene> {};

TEST_P(RunCommandBadInput, ExitsWithTwoAndWritesNothing) {
  const BadScene bad = GetParam();
  const Result result = run("run " + write_scene(bad.extra_or_solver).string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find(bad.expected), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out())) << "output written for bad input";
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, RunCommandBadInput,
    ::testing::Values(BadScene{"UnknownSolver", "  type: quasistatic\n", "quasistatic"},
                      BadScene{"UnknownKey", "  type: static\n  load_stepz: 3\n", "load_stepz"},
                      BadScene{"MissingDt", "  type: implicit\n  steps: 3\n", "dt"},
                      BadScene{"UnknownGroup", "  type: static\nprescribed: [{region: nowhere, displacement: [0, 1]}]\n",
                               "nowhere"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST_F(RunCommand, MissingSceneIsExitTwo) {
  const Result result = run("run " + (directory_ / "absent.yaml").string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("absent.yaml"), std::string::npos) << result.output;
}

TEST_F(RunCommand, MissingMeshIsExitTwoNamingTheFile) {
  fs::remove(directory_ / "beam.msh");
  const Result result = run("run " + write_scene(kStatic).string());
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("beam.msh"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(RunCommand, InvalidMaterialIsExitTwo) {
  const Result result = run("run " + write_scene(kStatic).string() + " --set materials.0.poisson=0.5");
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("poisson"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(RunCommand, InvertedElementAtRestIsExitTwoNamingIt) {
  // Two unit squares; the second is numbered clockwise (negative Jacobian).
  std::ofstream(directory_ / "beam.msh") << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
                                            "$PhysicalNames\n1\n1 1 \"clamp\"\n$EndPhysicalNames\n"
                                            "$Nodes\n6\n1 0 0 0\n2 1 0 0\n3 2 0 0\n4 0 1 0\n5 1 1 0\n6 2 1 0\n$EndNodes\n"
                                            "$Elements\n3\n1 1 2 1 1 1 4\n7 3 2 0 1 1 2 5 4\n8 3 2 0 1 2 5 6 3\n"
                                            "$EndElements\n";
  const Result result = run("run " + write_scene(kStatic).string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("id 8"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("non-positive Jacobian"), std::string::npos) << result.output;
  EXPECT_FALSE(fs::exists(out()));
}

TEST_F(RunCommand, NewtonDivergenceIsExitThreeWithTheLastGoodState) {
  // A very soft beam in one load step and two Newton iterations cannot converge.
  const Result result = run("run " + write_scene(kStatic).string() +
                            " --set materials.0.young=1e4 --set solver.max_iterations=2");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("Newton did not converge in load step 1/4"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out() / "last_good.vtu"));
  EXPECT_FALSE(fs::exists(out() / "final.vtu"));
  EXPECT_NE(read(out() / "summary.json").find("\"status\": \"failed\""), std::string::npos);
}

TEST_F(RunCommand, ExplicitBlowUpIsExitThree) {
  const Result result = run("run " + write_scene("  type: explicit\n  dt: 0.01\n  steps: 400\n").string());
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("stable time step"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out() / "last_good.vtu"));
}

}  // namespace
