// output.track in a scene: parsing, duplicate and file-name checks,
// validate_against_mesh (unknown group, group without cells), and `tensormass run`
// refusing such a scene before writing anything.
#include <gtest/gtest.h>

#include "tensormass/common/errors.hpp"
#include "tensormass/meshing/beam.hpp"
#include "tensormass/scene/scene.hpp"
#include "tensormass/simulation/track.hpp"
#include "track_test_support.hpp"

namespace {

using tensormass::InputError;
using track_test::TempDir;

/// A valid static scene; line numbers matter to the tests.
const std::string kScene =
    "mesh: beam.msh\n"                                                           // 1
    "materials:\n"                                                               // 2
    "  - {region: all, law: stvk, young: 1.0e6, poisson: 0.3, density: 1000}\n"  // 3
    "fixed: [clamp]\n"                                                           // 4
    "solver: {type: static, load_steps: 2}\n"                                    // 5
    "output:\n"                                                                  // 6
    "  directory: out\n"                                                         // 7
    "  track:\n"                                                                 // 8
    "    - body\n";                                                              // 9

/// The message of the InputError that `f` throws (a test failure when none).
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

tensormass::Mesh beam() {
  tensormass::BeamSpec spec;
  spec.cells = {6, 2, 1};
  spec.size = {3.0, 1.0, 1.0};
  return tensormass::make_beam(spec);
}

TEST(TrackScene, ReadsTheGroupsAndTheirLines) {
  TempDir dir;
  const auto scene = tensormass::load_scene(dir.write("scene.yaml", kScene + "    - tip\n"));
  ASSERT_EQ(scene.output.track, (std::vector<std::string>{"body", "tip"}));
  EXPECT_EQ(scene.output.track_lines, (std::vector<int>{9, 10}));
}

TEST(TrackScene, AbsentMeansNoTrack) {
  TempDir dir;
  const auto scene = tensormass::load_scene(dir.write("scene.yaml", kScene.substr(0, kScene.find("  track:"))));
  EXPECT_TRUE(scene.output.track.empty());
}

TEST(TrackScene, SetOverrideWorks) {
  TempDir dir;
  const auto scene = tensormass::load_scene(dir.write("scene.yaml", kScene), {"output.track=[tip, body]"});
  EXPECT_EQ(scene.output.track, (std::vector<std::string>{"tip", "body"}));
}

TEST(TrackScene, NotAListIsAnError) {
  TempDir dir;
  const std::string message = error_of([&] {
    tensormass::load_scene(dir.write("scene.yaml", kScene.substr(0, kScene.find("  track:")) + "  track: body\n"));
  });
  EXPECT_NE(message.find("scene.yaml:8"), std::string::npos) << message;
  EXPECT_NE(message.find("output.track"), std::string::npos) << message;
  EXPECT_NE(message.find("list of group names"), std::string::npos) << message;
}

TEST(TrackScene, GroupListedTwiceIsAnError) {
  TempDir dir;
  const std::string message =
      error_of([&] { tensormass::load_scene(dir.write("scene.yaml", kScene + "    - body\n")); });
  EXPECT_NE(message.find("scene.yaml:10"), std::string::npos) << message;
  EXPECT_NE(message.find("listed twice"), std::string::npos) << message;
}

TEST(TrackScene, GroupsWithTheSameFileNameAreAnError) {
  TempDir dir;
  const std::string message =
      error_of([&] { tensormass::load_scene(dir.write("scene.yaml", kScene + "    - a b\n    - a/b\n")); });
  EXPECT_NE(message.find("scene.yaml:11"), std::string::npos) << message;
  EXPECT_NE(message.find("track_a_b.csv"), std::string::npos) << message;
}

TEST(TrackScene, FileNameKeepsPlainCharacters) {
  EXPECT_EQ(tensormass::track_file_name("tumour-1.left_lobe"), "track_tumour-1.left_lobe.csv");
  EXPECT_EQ(tensormass::track_file_name("left lung/1"), "track_left_lung_1.csv");
}

TEST(TrackScene, UnknownGroupNamesFileLineAndGroups) {
  TempDir dir;
  const auto scene = tensormass::load_scene(dir.write("scene.yaml", kScene + "    - tumour\n"));
  const tensormass::Mesh mesh = beam();
  const std::string message = error_of([&] { tensormass::validate_against_mesh(scene, mesh); });
  EXPECT_NE(message.find("scene.yaml:10: output.track[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("'tumour'"), std::string::npos) << message;
  EXPECT_NE(message.find("clamp, tip, body"), std::string::npos) << message;
}

TEST(TrackScene, GroupWithoutCellsIsAnError) {
  TempDir dir;
  const auto scene = tensormass::load_scene(dir.write("scene.yaml", kScene + "    - clamp\n"));
  const tensormass::Mesh mesh = beam();
  const std::string message = error_of([&] { tensormass::validate_against_mesh(scene, mesh); });
  EXPECT_NE(message.find("scene.yaml:10: output.track[1]"), std::string::npos) << message;
  EXPECT_NE(message.find("group 'clamp' has no cells"), std::string::npos) << message;
}

TEST(TrackScene, RunRefusesBadTracksBeforeWritingAnything) {
  TempDir dir;
  ASSERT_EQ(track_test::tensormass("beam --dim 2 --cells 6,2 --size 3,1 -o " + dir.file("beam.msh")).exit_code, 0);
  for (const char* group : {"tumour", "tip"}) {
    const std::string scene = dir.write("scene.yaml", kScene + "    - " + group + "\n");
    const track_test::Result result = track_test::tensormass("run " + scene);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_NE(result.output.find("scene.yaml:10: output.track[1]"), std::string::npos) << result.output;
    EXPECT_FALSE(std::filesystem::exists(dir.path() / "out")) << "output written for bad input";
  }
}

}  // namespace
