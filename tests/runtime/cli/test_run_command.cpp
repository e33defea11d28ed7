// `tensormass run` end to end through the binary: outputs, exit codes 0, 2,
// 3 and 4, nothing written on bad input, last_good.vtu on a numerical
// failure, one run per output directory, no temporaries left behind.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

#include "support/test_support.hpp"
#include "tensormass/common/version.hpp"

namespace {

namespace fs = std::filesystem;

using test_support::read_file;
using test_support::Result;

Result run(const std::string& arguments) { return test_support::tensormass(arguments); }

class RunCommand : public ::testing::Test {
 protected:
  void SetUp() override {
    const Result beam = run("beam --dim 2 --cells 20,4 --size 5,1 -o " + dir_.file("beam.msh"));
    ASSERT_EQ(beam.exit_code, 0) << beam.output;
  }

  fs::path write_scene(const std::string& solver, const std::string& extra = "") {
    const fs::path path = dir_.path() / "scene.yaml";
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
  fs::path out() const { return dir_.path() / "out"; }

  test_support::TempDir dir_;
};

const char* kStatic = "  type: static\n  load_steps: 4\n  tolerance: 1.0e-10\n";
const char* kImplicit = "  type: implicit\n  dt: 0.01\n  steps: 6\n  newton_iterations: 2\n";

TEST_F(RunCommand, StaticSceneWritesFinalFramesSeriesAndSummary) {
  const Result result = run("run " + write_scene(kStatic).string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const char* name : {"final.vtu", "frame_000002.vtu", "frame_000004.vtu", "series.pvd", "summary.json"})
    EXPECT_TRUE(fs::exists(out() / name)) << name;
  const auto summary = nlohmann::json::parse(read_file(out() / "summary.json"));
  EXPECT_EQ(summary["status"], "ok");
  EXPECT_EQ(summary["version"], tensormass::kVersion);
  EXPECT_EQ(summary["steps"], 4);
  EXPECT_EQ(summary["elements_per_law"], nlohmann::json({{"stvk", 80}}));
  for (const char* key :
       {"time_per_step_ms", "time_per_phase_s", "newton_iterations", "linear_iterations", "switches", "law_ids"})
    EXPECT_TRUE(summary.contains(key)) << key << "\n" << summary.dump(2);
  EXPECT_NE(result.output.find("max displacement"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(out()))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << entry.path();
}

// Idle OpenMP threads spin briefly, then sleep, unless the user chose
// otherwise (common/thread_defaults.hpp); the summary says what the run used.
TEST_F(RunCommand, WaitPolicyIsPassiveByDefaultAndTheUsersOtherwise) {
  const std::string scene = write_scene(kStatic).string();
  const std::string binary = "'" TENSORMASS_BINARY "' run ";
  ASSERT_EQ(test_support::shell("env -u OMP_WAIT_POLICY -u GOMP_SPINCOUNT " + binary + scene).exit_code, 0);
  const auto policy = [&] {
    const auto solver = nlohmann::json::parse(read_file(out() / "summary.json"))["solver"];
    return solver["omp_wait_policy"].get<std::string>() + " " + solver["gomp_spincount"].get<std::string>();
  };
  EXPECT_EQ(policy(), "passive 10000");
  ASSERT_EQ(test_support::shell("env -u OMP_WAIT_POLICY GOMP_SPINCOUNT=0 " + binary + scene).exit_code, 0);
  EXPECT_EQ(policy(), "passive 0");
  ASSERT_EQ(test_support::shell("env -u GOMP_SPINCOUNT OMP_WAIT_POLICY=active " + binary + scene).exit_code, 0);
  EXPECT_EQ(policy(), "active unset");
}

TEST_F(RunCommand, FinalVtuOpensInMeshioWithThreeComponentDisplacement) {
  ASSERT_EQ(run("run --quiet " + write_scene(kImplicit).string()).exit_code, 0);
  const Result check = test_support::python(
      "-c \"import meshio,sys; m=meshio.read(sys.argv[1]); "
      "d=m.point_data['displacement']; assert d.shape==(len(m.points),3); "
      "assert 'law_id' in m.cell_data and 'element_type' in m.cell_data; "
      "assert abs(d[:,1]).max()>0\" " +
      (out() / "final.vtu").string());
  EXPECT_EQ(check.exit_code, 0) << check.output;
}

TEST_F(RunCommand, SetOverridesAKey) {
  const Result result = run("run " + write_scene(kImplicit).string() + " --set solver.steps=2 --set output.every=0");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(read_file(out() / "summary.json").find("\"steps\": 2"), std::string::npos);
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
  const char* expected;         ///< in the one-line message
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
                      BadScene{"UnknownGroup",
                               "  type: static\nprescribed: [{region: nowhere, displacement: [0, 1]}]\n", "nowhere"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST_F(RunCommand, ASecondRunIntoTheSameDirectoryIsRefusedNamingTheHolder) {
  fs::create_directories(out());
  const int fd = ::open((out() / ".tensormass.lock").c_str(), O_RDWR | O_CREAT, 0644);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // this process plays the running run
  ASSERT_EQ(::write(fd, "4242\n", 5), 5);
  const Result second = run("run " + write_scene(kStatic).string());
  ::close(fd);
  EXPECT_EQ(second.exit_code, 2) << second.output;
  EXPECT_NE(second.output.find("output directory " + out().string() + " is in use by another run (process 4242)"),
            std::string::npos)
      << second.output;
  EXPECT_FALSE(fs::exists(out() / "summary.json"));
  EXPECT_EQ(run("run --quiet " + write_scene(kStatic).string()).exit_code, 0);  // released: the next run goes
}

TEST_F(RunCommand, ATemporaryOfAKilledRunIsRemovedByTheNextRun) {
  fs::create_directories(out());
  std::ofstream(out() / "frame_000002.vtu.tmp-99999") << "<VTKFile";
  const Result result = run("run --quiet " + write_scene(kStatic).string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  for (const auto& entry : fs::directory_iterator(out()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST_F(RunCommand, AFailedWriteIsExitFourWithAFailedSummaryAndNoPartialFile) {
  // A file-size limit makes every write past 8 KiB fail (EFBIG, SIGXFSZ
  // ignored) as a full disk would: the frames of this beam (14 KB) are larger,
  // its summary.json (2 KB) is not.
  const Result result = test_support::shell("trap '' XFSZ; ulimit -f 8; exec '" TENSORMASS_BINARY "' run --quiet " +
                                            write_scene(kStatic).string());
  EXPECT_EQ(result.exit_code, 4) << result.output;
  EXPECT_NE(result.output.find("tensormass: output failure: cannot write " + (out() / "frame_000002.vtu").string()),
            std::string::npos)
      << result.output;
  const auto summary = nlohmann::json::parse(read_file(out() / "summary.json"));
  EXPECT_EQ(summary["status"], "failed");
  EXPECT_NE(summary["error"].get<std::string>().find("frame_000002.vtu"), std::string::npos);
  for (const auto& entry : fs::directory_iterator(out())) {
    const std::string name = entry.path().filename().string();
    EXPECT_EQ(name.find(".tmp-"), std::string::npos) << name;
    EXPECT_NE(name, "frame_000002.vtu");
  }
}

TEST_F(RunCommand, MissingSceneIsExitTwo) {
  const Result result = run("run " + dir_.file("absent.yaml"));
  EXPECT_EQ(result.exit_code, 2);
  EXPECT_NE(result.output.find("absent.yaml"), std::string::npos) << result.output;
}

TEST_F(RunCommand, MissingMeshIsExitTwoNamingTheFile) {
  fs::remove(dir_.path() / "beam.msh");
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
  std::ofstream(dir_.path() / "beam.msh")
      << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n"
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
  const Result result =
      run("run " + write_scene(kStatic).string() + " --set materials.0.young=1e4 --set solver.max_iterations=2");
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("Newton did not converge in load step 1/4"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out() / "last_good.vtu"));
  EXPECT_FALSE(fs::exists(out() / "final.vtu"));
  EXPECT_NE(read_file(out() / "summary.json").find("\"status\": \"failed\""), std::string::npos);
}

TEST_F(RunCommand, ExplicitBlowUpIsExitThree) {
  const Result result = run("run " + write_scene("  type: explicit\n  dt: 0.01\n  steps: 400\n").string());
  EXPECT_EQ(result.exit_code, 3) << result.output;
  EXPECT_NE(result.output.find("stable time step"), std::string::npos) << result.output;
  EXPECT_TRUE(fs::exists(out() / "last_good.vtu"));
}

}  // namespace
