// `tensormass render` end to end through the binary: a 2D quad beam and a 3D
// tet beam, run by `tensormass run`, given a fake `state` cell array with
// meshio (0..1 criterion / threshold, 2 = switched), drawn to PNGs; bad
// input exits 2 and writes nothing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <string>

#include "support/test_support.hpp"

namespace {

namespace fs = std::filesystem;

using test_support::Result;
using test_support::tensormass;

/// Adds `state` (and matching law_id: 2 where switched) to a result, as the adaptive model will.
constexpr const char* kAddState = R"(import sys
import meshio
import numpy as np
mesh = meshio.read(sys.argv[1])
centres = np.concatenate([mesh.points[np.asarray(b.data)].mean(axis=1) for b in mesh.cells])
state = np.clip((1 - centres[:, 0] / 6) * (0.5 + abs(centres[:, 1] - 0.5)), 0, 1)
state[state > 0.8] = 2.0
law = np.where(state == 2.0, 2.0, 0.0)
sizes = np.cumsum([len(b.data) for b in mesh.cells])[:-1]
mesh.cell_data["state"] = np.split(state, sizes)
mesh.cell_data["law_id"] = np.split(law, sizes)
meshio.write(sys.argv[2], mesh)
)";

class Render : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::make_unique<test_support::TempDir>();
    directory_ = dir_->path();
    std::ofstream(directory_ / "add_state.py") << kAddState;
    std::ofstream(directory_ / "scene.yaml")
        << "mesh: beam.msh\n"
           "materials:\n"
           "  - {region: all, law: stvk, young: 1.0e7, poisson: 0.3, density: 1000}\n"
           "fixed: [clamp]\n"
           "loads:\n"
           "  gravity: [0, -9.81, 0]\n"
           "solver: {type: static, load_steps: 4, tolerance: 1.0e-10}\n"
           "output: {directory: out, every: 0}\n";
    make_result("2d", "--cells 30,5");
    make_result("3d", "--dim 3 --cells 12,3,3 --type tet6");
  }
  static void TearDownTestSuite() { dir_.reset(); }

  /// DIR/NAME/out/final.vtu (run) and DIR/NAME/out/state.vtu (with the fake state).
  static void make_result(const std::string& name, const std::string& beam_options) {
    const fs::path case_directory = directory_ / name;
    fs::create_directories(case_directory);
    fs::copy_file(directory_ / "scene.yaml", case_directory / "scene.yaml");
    const Result beam = tensormass("beam " + beam_options + " -o " + (case_directory / "beam.msh").string());
    ASSERT_EQ(beam.exit_code, 0) << beam.output;
    const Result run = tensormass("run " + (case_directory / "scene.yaml").string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    const fs::path out = case_directory / "out";
    const Result state = test_support::python((directory_ / "add_state.py").string() + " " +
                                              (out / "final.vtu").string() + " " + (out / "state.vtu").string());
    ASSERT_EQ(state.exit_code, 0) << state.output;
  }

  /// Checks a PNG: signature, width from the IHDR chunk, a plausible size.
  static void expect_png(const fs::path& path, unsigned width) {
    ASSERT_TRUE(fs::exists(path)) << path;
    const std::string bytes = test_support::read_file(path);
    ASSERT_GT(bytes.size(), 10000u) << path;
    EXPECT_EQ(bytes.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << path;
    EXPECT_EQ(bytes.substr(12, 4), "IHDR");
    const auto byte = [&](std::size_t i) { return static_cast<unsigned>(static_cast<unsigned char>(bytes[i])); };
    EXPECT_EQ(byte(16) << 24 | byte(17) << 16 | byte(18) << 8 | byte(19), width) << path;
  }

  /// No image and no temporary left in the scratch directory's top level.
  static void expect_no_image(const std::string& stem) {
    for (const fs::directory_entry& entry : fs::directory_iterator(directory_))
      EXPECT_NE(entry.path().filename().string().rfind(stem, 0), 0u) << "left behind: " << entry.path();
  }

  static inline std::unique_ptr<test_support::TempDir> dir_;  ///< shared by the suite's tests
  static inline fs::path directory_;
};

TEST_F(Render, Beam2DStateDefaultField) {
  const fs::path image = directory_ / "beam2d.png";
  const Result result = tensormass("render " + (directory_ / "2d/out/state.vtu").string() + " -o " + image.string());
  ASSERT_EQ(result.exit_code, 0) << result.output;
  expect_png(image, 1600);
  expect_no_image("beam2d.png.tmp");
}

TEST_F(Render, Beam3DTetStateWidthAndTitle) {
  const fs::path image = directory_ / "beam3d.png";
  const Result result = tensormass("render " + (directory_ / "3d/out/state.vtu").string() + " -o " + image.string() +
                                   " --width 1000 --title 'tet beam'");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  expect_png(image, 1000);
}

TEST_F(Render, LawIdAndDisplacementAndCellFields) {
  const std::string final2d = (directory_ / "2d/out/final.vtu").string();
  const std::string final3d = (directory_ / "3d/out/final.vtu").string();
  for (const auto& [arguments, name] :
       {std::pair{final2d, "law2d.png"}, std::pair{final2d + " --field displacement --rest", "disp2d.png"},
        std::pair{final3d + " --field displacement", "disp3d.png"},
        std::pair{final3d + " --field element_type", "type3d.png"}}) {
    const Result result = tensormass("render " + arguments + " --width 800 -o " + (directory_ / name).string());
    ASSERT_EQ(result.exit_code, 0) << arguments << "\n" << result.output;
    expect_png(directory_ / name, 800);
  }
}

TEST_F(Render, MissingFileExits2WithoutImage) {
  const Result result =
      tensormass("render " + (directory_ / "absent.vtu").string() + " -o " + (directory_ / "absent.png").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("absent.vtu"), std::string::npos) << result.output;
  expect_no_image("absent.png");
}

TEST_F(Render, UnknownFieldExits2NamingIt) {
  const Result result = tensormass("render " + (directory_ / "2d/out/final.vtu").string() + " --field R_BOGUS -o " +
                                   (directory_ / "bogus.png").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("R_BOGUS"), std::string::npos) << result.output;
  expect_no_image("bogus.png");
}

TEST_F(Render, UnreadableFileExits2WithoutImage) {
  std::ofstream(directory_ / "garbage.vtu") << "not a VTU file\n";
  const Result result =
      tensormass("render " + (directory_ / "garbage.vtu").string() + " -o " + (directory_ / "garbage.png").string());
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("garbage.vtu"), std::string::npos) << result.output;
  expect_no_image("garbage.png");
}

TEST_F(Render, BadCommandLinesExit2) {
  const std::string frame = (directory_ / "2d/out/final.vtu").string();
  const std::string image = (directory_ / "bad.png").string();
  for (const std::string& arguments :
       {frame + " -o " + image + " --colour red", frame, frame + " -o " + image + " --width 12",
        frame + " -o " + image + " --rest --deformed", frame + " -o " + (directory_ / "no/such/dir.png").string()}) {
    const Result result = tensormass("render " + arguments);
    EXPECT_EQ(result.exit_code, 2) << arguments << "\n" << result.output;
  }
  expect_no_image("bad.png");
  EXPECT_EQ(tensormass("render --help").exit_code, 0);
}

}  // namespace
