// RunStreams: a run's track and record files, new ones replacing an earlier
// run's unfinished files, resumed ones checked all before any is cut back.
// (End to end, killed and resumed runs: tests/examples/run_kill_resume.sh.)
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "simulation/run_streams.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/meshing/beam.hpp"

namespace tensormass::detail {
namespace {

using test_support::read_file;
using test_support::TempDir;

Mesh quad_beam() {
  BeamSpec spec;
  spec.dim = 2;
  spec.cells = {4, 2, 1};
  spec.size = {2.0, 1.0, 1.0};
  spec.phases = {{"quad4", 1.0}};
  return make_beam(spec);
}

class RunStreamsTest : public ::testing::Test {
 protected:
  Mesh mesh_ = quad_beam();
  std::vector<GroupTrack> tracks_{GroupTrack(mesh_, "body", std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7}),
                                  GroupTrack(mesh_, "end", std::vector<int>{3, 7})};
  std::vector<double> u_ = std::vector<double>(static_cast<std::size_t>(2 * mesh_.node_count()), 0.0);
  TempDir dir_;

  /// A run of `rows` rows per track and one record per row, checkpointed after `marked` rows.
  Checkpoint run(int rows, int marked) {
    RunStreams streams(dir_.path().string(), tracks_, true, nullptr, "");
    Checkpoint saved;
    for (int k = 0; k < rows; ++k) {
      if (k == marked) save(streams, saved);
      for (std::size_t t = 0; t < tracks_.size(); ++t) streams.append_track_row(t, tracks_[t].record(0.1 * k, u_));
      streams.append_record({k, 0, 0, {{"hooke", 8}}});
    }
    if (marked >= rows) save(streams, saved);
    return saved;
  }
  static void save(RunStreams& streams, Checkpoint& saved) {
    saved.tracks.clear();
    for (const io::StreamMark& mark : streams.track_marks()) saved.tracks.push_back({mark, {}});
    saved.adaptivity_records = streams.record_mark();
  }
};

TEST_F(RunStreamsTest, FinishedFilesAreListedInTheReport) {
  {
    RunStreams streams(dir_.path().string(), tracks_, true, nullptr, "");
    streams.append_track_row(0, tracks_[0].record(0.0, u_));
    streams.append_record({0, 2, 0, {{"stvk", 2}}});
    RunReport report;
    streams.finish(tracks_, report);
    EXPECT_EQ(report.files, (std::vector<std::string>{"track_body.csv", "track_end.csv", "adaptivity.jsonl"}));
    ASSERT_EQ(report.tracks.size(), 2u);
    EXPECT_EQ(report.tracks[1], (std::pair<std::string, std::string>{"end", "track_end.csv"}));
  }
  EXPECT_EQ(read_file(dir_.file("track_end.csv")), "time,x,y,z,ux,uy,uz\n");
  EXPECT_EQ(read_file(dir_.file("adaptivity.jsonl")),
            "{\"step\":0,\"upgrades\":2,\"downgrades\":0,\"elements_per_law\":{\"stvk\":2}}\n");
}

TEST_F(RunStreamsTest, ANewRunRemovesTheUnfinishedFilesOfAnEarlierOne) {
  dir_.write("track_old_group.csv.partial", "time,x,y,z,ux,uy,uz\n");
  dir_.write("adaptivity.jsonl.partial", "{}\n");
  dir_.write("track_notes.csv", "kept: not a run's unfinished file\n");
  RunStreams streams(dir_.path().string(), tracks_, false, nullptr, "");
  EXPECT_EQ(dir_.files(),
            (std::vector<std::string>{"track_body.csv.partial", "track_end.csv.partial", "track_notes.csv"}));
}

TEST_F(RunStreamsTest, AResumedRunCutsEveryFileBackToItsMark) {
  const Checkpoint saved = run(5, 3);
  RunStreams resumed(dir_.path().string(), tracks_, true, &saved, "checkpoint.bin");
  RunReport report;
  resumed.finish(tracks_, report);
  EXPECT_EQ(test_support::read_lines(dir_.path() / "track_end.csv").size(), 4u);  // header and rows 0..2
  EXPECT_EQ(test_support::read_lines(dir_.path() / "adaptivity.jsonl").size(), 3u);
}

TEST_F(RunStreamsTest, AResumeRefusedForOneFileChangesNoOther) {
  const Checkpoint saved = run(5, 3);
  const std::string body = read_file(dir_.file("track_body.csv.partial"));
  std::string records = read_file(dir_.file("adaptivity.jsonl.partial"));
  records[2] = 'X';
  dir_.write("adaptivity.jsonl.partial", records);
  try {
    RunStreams resumed(dir_.path().string(), tracks_, true, &saved, "checkpoint.bin");
    ADD_FAILURE() << "an edited record file was resumed";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("adaptivity.jsonl.partial is not the file"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_file(dir_.file("track_body.csv.partial")), body);  // rows 3 and 4 still there
}

TEST_F(RunStreamsTest, ACheckpointOfOtherTracksIsRefused) {
  Checkpoint saved = run(2, 2);
  saved.tracks.pop_back();
  try {
    RunStreams resumed(dir_.path().string(), tracks_, true, &saved, "out/checkpoint.bin");
    ADD_FAILURE() << "resumed with one track of two";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("out/checkpoint.bin holds 1 tracks, the scene asks for 2"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tensormass::detail
