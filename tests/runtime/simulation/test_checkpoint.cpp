// Checkpoints (checkpoint.cpp): the file round-trips, a damaged or forged
// one is a clear input error naming the field, fingerprints follow what
// changes a run and nothing else, and `tensormass run --resume` refuses
// another run's checkpoint and one whose step, time or frames its run
// cannot have written.
// (The SIGKILL-and-resume runs, bitwise equal to uninterrupted ones, with
// and without the adaptive model, are tests/examples/run_kill_resume.sh.)
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>

#include "support/cantilever.hpp"
#include "support/test_support.hpp"
#include "tensormass/common/errors.hpp"
#include "tensormass/simulation/checkpoint.hpp"

namespace tensormass {
namespace {

namespace fs = std::filesystem;
using test_support::expect_contains;
using test_support::TempDir;

Checkpoint sample() {
  Checkpoint c;
  c.mesh_fingerprint = 11;
  c.scene_fingerprint = 22;
  c.state = {{0.1, -0.2, 1e-300}, {3.0, 4.0, 5.0}, 0.75, 9, {1.5}, {0.25, 0.5, 0.125}, {}, {-7.5, 2e-12}};
  c.linear_solver = {1.0, 2.0, 3.0};
  c.statistics.newton_iterations = 18;
  c.statistics.shortened_steps = 2;
  c.statistics.linear_iterations = 123456789012;
  c.statistics.newton_per_step = {2, 2, 3};
  c.statistics.step_ms = {1.5, 2.5, 3.5};
  c.step_solve_ms = {0.5};
  c.tracks = {{{2, 120, 0xfedcba9876543210u}, {0.0, 0.0, 1e-9}}};
  c.series = {{0.05, "frame_000005.vtu"}, {0.1, "frame_000010.vtu"}};
  c.refining = true;
  SavedRefinement& r = c.refinement;
  r.coarsens = {0, 0, 1};
  r.max_levels = {2, 2, 0};
  r.offsets = {0, 2, 3, 5};
  r.cells = {4, 7, 1, 0, 9};
  r.calm = {0, 3, 1};
  r.peak = 0.125;
  r.event_steps = {0, 4};
  r.event_cells = {50, 86};
  r.event_level_offsets = {0, 1, 3};
  r.event_levels = {50, 44, 24};
  return c;
}

TEST(Checkpoint, RoundTripsEveryField) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  const Checkpoint c = sample();
  write_checkpoint(path, c);
  const Checkpoint r = read_checkpoint(path);
  EXPECT_EQ(r.mesh_fingerprint, 11u);
  EXPECT_EQ(r.scene_fingerprint, 22u);
  EXPECT_EQ(r.state.displacement, c.state.displacement);
  EXPECT_EQ(r.state.velocity, c.state.velocity);
  EXPECT_EQ(r.state.time, 0.75);
  EXPECT_EQ(r.state.step, 9);
  EXPECT_EQ(r.state.warm_start, c.state.warm_start);
  EXPECT_EQ(r.state.previous_displacement, c.state.previous_displacement);
  EXPECT_TRUE(r.state.earlier_displacement.empty());
  EXPECT_EQ(r.state.viscous_history, c.state.viscous_history);
  EXPECT_EQ(r.linear_solver, c.linear_solver);
  EXPECT_EQ(r.statistics.newton_iterations, 18);
  EXPECT_EQ(r.statistics.shortened_steps, 2);
  EXPECT_EQ(r.statistics.linear_iterations, 123456789012);
  EXPECT_EQ(r.statistics.newton_per_step, c.statistics.newton_per_step);
  EXPECT_EQ(r.statistics.step_ms, c.statistics.step_ms);
  EXPECT_EQ(r.step_solve_ms, c.step_solve_ms);
  ASSERT_EQ(r.tracks.size(), 1u);
  EXPECT_EQ(r.tracks[0].file.rows, 2u);
  EXPECT_EQ(r.tracks[0].file.bytes, 120u);
  EXPECT_EQ(r.tracks[0].file.checksum, 0xfedcba9876543210u);
  EXPECT_EQ(r.tracks[0].first_shift, c.tracks[0].first_shift);
  ASSERT_EQ(r.series.size(), 2u);
  EXPECT_EQ(r.series[1].file, "frame_000010.vtu");
  EXPECT_EQ(r.series[1].time, 0.1);
  ASSERT_TRUE(r.refining);
  const SavedRefinement& a = r.refinement;
  const SavedRefinement& b = c.refinement;
  EXPECT_EQ(a.coarsens, b.coarsens);
  EXPECT_EQ(a.max_levels, b.max_levels);
  EXPECT_EQ(a.offsets, b.offsets);
  EXPECT_EQ(a.cells, b.cells);
  EXPECT_EQ(a.calm, b.calm);
  EXPECT_EQ(a.peak, b.peak);
  EXPECT_EQ(a.event_steps, b.event_steps);
  EXPECT_EQ(a.event_cells, b.event_cells);
  EXPECT_EQ(a.event_level_offsets, b.event_level_offsets);
  EXPECT_EQ(a.event_levels, b.event_levels);
}

TEST(Checkpoint, AnInconsistentRefinementHistoryIsRefused) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  Checkpoint c = sample();
  c.refinement.offsets.back() = 4;  // one marked cell short
  write_checkpoint(path, c);
  try {
    read_checkpoint(path);
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"checkpoint " + path, "inconsistent refinement history"});
  }
}

TEST(Checkpoint, EveryTruncationIsAnInputErrorNamingTheFile) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint(path, sample());
  const std::string bytes = test_support::read_file(path);
  for (std::size_t length = 0; length < bytes.size(); length += 7) {
    std::ofstream(path, std::ios::binary | std::ios::trunc).write(bytes.data(), static_cast<std::streamsize>(length));
    try {
      read_checkpoint(path);
      ADD_FAILURE() << "a checkpoint cut at " << length << " bytes was read";
    } catch (const InputError& e) {
      expect_contains(e.what(), {"checkpoint " + path});
    }
  }
  std::ofstream(path, std::ios::binary | std::ios::trunc) << "mesh: beam.msh\n";
  EXPECT_THROW(read_checkpoint(path), InputError);
  EXPECT_THROW(read_checkpoint(dir.file("missing.bin")), InputError);
}

TEST(Checkpoint, AFlippedBitAnywhereIsRefused) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint(path, sample());
  const std::string bytes = test_support::read_file(path);
  for (std::size_t at = 0; at < bytes.size(); at += 5) {
    std::string damaged = bytes;
    damaged[at] = static_cast<char>(damaged[at] ^ 0x10);
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(damaged.data(), static_cast<std::streamsize>(damaged.size()));
    try {
      read_checkpoint(path);
      ADD_FAILURE() << "a checkpoint with byte " << at << " flipped was read";
    } catch (const InputError& e) {
      expect_contains(e.what(), {"checkpoint " + path});
    }
  }
  std::string payload_flip = bytes;
  payload_flip[bytes.size() - 3] = static_cast<char>(payload_flip[bytes.size() - 3] ^ 1);
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(payload_flip.data(), static_cast<std::streamsize>(payload_flip.size()));
  try {
    read_checkpoint(path);
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    expect_contains(e.what(), {"checksum does not match"});
  }
}

/// read_checkpoint of `c` written with a valid checksum: the InputError's text.
std::string refusal(const Checkpoint& c) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  write_checkpoint(path, c);
  try {
    read_checkpoint(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "read";
}

TEST(Checkpoint, ForgedFieldsAreRefusedNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Checkpoint c = sample();
  c.state.step = -1000000;
  expect_contains(refusal(c), {"state.step", "negative"});
  c = sample();
  c.state.time = nan;
  expect_contains(refusal(c), {"state.time"});
  c = sample();
  c.state.displacement[1] = nan;
  expect_contains(refusal(c), {"state.displacement", "not finite"});
  c = sample();
  c.state.velocity[0] = std::numeric_limits<double>::infinity();
  expect_contains(refusal(c), {"state.velocity"});
  c = sample();
  c.series[1].file = "../../outside.vtu";
  expect_contains(refusal(c), {"series", "a file a run does not write"});
  c = sample();
  c.series[1].file = "frame_99999999999999999999.vtu";  // a step past any int
  expect_contains(refusal(c), {"series", "a file a run does not write"});
  c = sample();
  c.series[1].file = "frame_000010.vtu\n<evil/>";
  expect_contains(refusal(c), {"series"});
  c = sample();
  c.series[0].time = 0.2;  // after the next frame's
  expect_contains(refusal(c), {"series", "out of order"});
  c = sample();
  c.series.assign(11, {0.1, "frame_000010.vtu"});  // more frames than the 9 steps could write
  expect_contains(refusal(c), {"series", "more frames than steps"});
  c = sample();
  c.tracks[0].first_shift[2] = nan;
  expect_contains(refusal(c), {"tracks", "not finite"});
  c = sample();
  c.tracks[0].file.rows = 11;  // more rows than the 9 steps and the start recorded
  expect_contains(refusal(c), {"tracks", "more rows"});
  EXPECT_EQ(refusal(sample()), "read");
}

TEST(Checkpoint, OnlyARegularFileIsRead) {
  TempDir dir;
  fs::create_directory(dir.path() / "checkpoint.bin");
  try {
    read_checkpoint(dir.file("checkpoint.bin"));
    ADD_FAILURE() << "a directory was read";
  } catch (const InputError& e) {
    expect_contains(e.what(), {dir.file("checkpoint.bin") + ": is a directory", "regular file"});
  }
  ASSERT_EQ(::mkfifo(dir.file("fifo.bin").c_str(), 0600), 0);
  EXPECT_THROW(read_checkpoint(dir.file("fifo.bin")), InputError);  // refused, not blocked on
}

TEST(Checkpoint, SceneFingerprintFollowsWhatChangesTheRun) {
  const Scene base = test::cantilever("stvk", SolverType::implicit_euler);
  const std::uint64_t reference = scene_fingerprint(base);
  Scene same = base;
  same.solver.threads = 2;  // results do not depend on the thread count
  same.solver.steps = 500;  // a dynamic run may be continued further
  same.output.directory = "elsewhere";
  EXPECT_EQ(scene_fingerprint(same), reference);
  auto differs = [&](auto change) {
    Scene other = base;
    change(other);
    return scene_fingerprint(other) != reference;
  };
  EXPECT_TRUE(differs([](Scene& s) { s.model.materials[0].constants["young"] *= 1.0000001; }));
  EXPECT_TRUE(differs([](Scene& s) { s.model.loads.gravity[1] = -9.8; }));
  EXPECT_TRUE(differs([](Scene& s) { s.solver.dt = 0.02; }));
  EXPECT_TRUE(differs([](Scene& s) { s.solver.predictor = StepPredictor::none; }));
  EXPECT_TRUE(differs([](Scene& s) { s.output.every = 3; }));
  EXPECT_TRUE(differs([](Scene& s) { s.refinement.enabled = true; }));
  EXPECT_TRUE(differs([](Scene& s) {
    s.refinement.enabled = true;
    s.refinement.calm_steps = 7;
  }));
  EXPECT_TRUE(differs([](Scene& s) {
    PrescribedSpec turn;
    turn.region = "tip";
    turn.rotates = true;
    turn.rotation.angle = 10;
    s.model.prescribed.push_back(turn);
  }));
  Scene statics = test::cantilever("stvk");
  const std::uint64_t static_reference = scene_fingerprint(statics);
  statics.solver.load_steps = 20;  // a static solve's load steps change every load factor
  EXPECT_NE(scene_fingerprint(statics), static_reference);
}

TEST(Checkpoint, MeshFingerprintFollowsNodesCellsAndGroups) {
  const Mesh mesh = test::beam(2, "quad4", {4, 2, 1});
  Mesh moved = mesh;
  moved.rest_positions[4] += 1e-12;
  Mesh regrouped = mesh;
  regrouped.groups.pop_back();
  EXPECT_EQ(mesh_fingerprint(mesh), mesh_fingerprint(test::beam(2, "quad4", {4, 2, 1})));
  EXPECT_NE(mesh_fingerprint(moved), mesh_fingerprint(mesh));
  EXPECT_NE(mesh_fingerprint(regrouped), mesh_fingerprint(mesh));
}

/// `tensormass run --resume` on a beam scene in a temporary directory.
class Resume : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto beam = test_support::tensormass("beam --dim 2 --cells 20,4 --size 5,1 -o " + dir_.file("beam.msh"));
    ASSERT_EQ(beam.exit_code, 0) << beam.output;
    write("young: 1.0e7");
    const auto first = test_support::tensormass("run --quiet " + dir_.file("scene.yaml"));
    ASSERT_EQ(first.exit_code, 0) << first.output;
    ASSERT_TRUE(fs::exists(dir_.path() / "out" / "checkpoint.bin"));
  }
  void write(const std::string& young, const std::string& extra = "") {
    dir_.write("scene.yaml", "mesh: beam.msh\nmaterials:\n  - {region: all, law: stvk, " + young +
                                 ", poisson: 0.3, density: 1000}\nfixed: [clamp]\nloads: {gravity: [0, -9.81]}\n"
                                 "solver: {type: implicit, dt: 0.01, steps: 10}\n"
                                 "output: {directory: out, checkpoint_every: 4}\n" +
                                 extra);
  }
  TempDir dir_;
};

TEST_F(Resume, ContinuesAFinishedRunFurther) {
  const auto more = test_support::tensormass("run " + dir_.file("scene.yaml") + " --resume --set solver.steps=14");
  ASSERT_EQ(more.exit_code, 0) << more.output;
  expect_contains(more.output, {"resuming from", "at step 8 (t = 0.08)"});
  expect_contains(test_support::read_file(dir_.path() / "out" / "summary.json"), {"\"resumed_from_step\": 8"});
}

TEST_F(Resume, RefusesAnotherScenesCheckpointAndWritesNothing) {
  write("young: 2.0e7");
  const auto before = test_support::read_file(dir_.path() / "out" / "summary.json");
  const auto refused = test_support::tensormass("run " + dir_.file("scene.yaml") + " --resume");
  EXPECT_EQ(refused.exit_code, 2);
  expect_contains(refused.output, {"checkpoint.bin was written for another version of", "scene.yaml"});
  EXPECT_EQ(test_support::read_file(dir_.path() / "out" / "summary.json"), before);
}

TEST_F(Resume, RefusesAnotherMeshesCheckpoint) {
  ASSERT_EQ(test_support::tensormass("beam --dim 2 --cells 20,5 --size 5,1 -o " + dir_.file("beam.msh")).exit_code, 0);
  const auto refused = test_support::tensormass("run " + dir_.file("scene.yaml") + " --resume");
  EXPECT_EQ(refused.exit_code, 2);
  expect_contains(refused.output, {"was written for another mesh than"});
}

// The track file is written row by row: a resumed run keeps the rows up to
// its checkpoint's and goes on; a track file that is not the checkpoint's
// is refused (exit 2) and left as it was.
TEST_F(Resume, KeepsTheTrackRowsOfTheCheckpointAndRefusesAnEditedTrackFile) {
  const std::string track = " --set output.track=[body]";
  const auto reference = test_support::tensormass("run --quiet " + dir_.file("scene.yaml") + track +
                                                  " --set solver.steps=14 --set output.directory=" + dir_.file("ref"));
  ASSERT_EQ(reference.exit_code, 0) << reference.output;
  const auto first = test_support::tensormass("run --quiet " + dir_.file("scene.yaml") + track);
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const fs::path file = dir_.path() / "out" / "track_body.csv";
  const std::string finished = test_support::read_file(file);
  EXPECT_EQ(std::count(finished.begin(), finished.end(), '\n'), 12);  // the header and steps 0 to 10
  const auto more =
      test_support::tensormass("run --quiet " + dir_.file("scene.yaml") + track + " --resume --set solver.steps=14");
  ASSERT_EQ(more.exit_code, 0) << more.output;  // from the checkpoint at step 8: rows 9 and 10 written again
  EXPECT_EQ(test_support::read_file(file), test_support::read_file(dir_.path() / "ref" / "track_body.csv"));
  EXPECT_FALSE(fs::exists(file.string() + ".partial"));

  std::string edited = test_support::read_file(file);
  edited[edited.find('\n') + 1] = edited[edited.find('\n') + 1] == '0' ? '1' : '0';
  dir_.write("out/track_body.csv", edited);
  const auto refused =
      test_support::tensormass("run " + dir_.file("scene.yaml") + track + " --resume --set solver.steps=14");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  expect_contains(refused.output, {"track_body.csv is not the file the checkpoint was written with"});
  EXPECT_EQ(test_support::read_file(file), edited);
  fs::remove(file);
  const auto missing =
      test_support::tensormass("run " + dir_.file("scene.yaml") + track + " --resume --set solver.steps=14");
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  expect_contains(missing.output, {"track_body.csv.partial is missing"});
}

/// The fixture's checkpoint changed by `forge` and written again, checksum
/// and all: the checksum alone does not make a checkpoint its run's.
class ForgedResume : public Resume {
 protected:
  std::string resume_forged(const std::function<void(Checkpoint&)>& forge) {
    const std::string path = (dir_.path() / "out" / "checkpoint.bin").string();
    Checkpoint c = read_checkpoint(path);
    forge(c);
    write_checkpoint(path, c);
    const auto before = test_support::read_file(dir_.path() / "out" / "summary.json");
    const auto refused = test_support::tensormass("run " + dir_.file("scene.yaml") + " --resume");
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_EQ(test_support::read_file(dir_.path() / "out" / "summary.json"), before);
    return refused.output;
  }
};

TEST_F(ForgedResume, AStepPastTheRunIsRefused) {
  expect_contains(resume_forged([](Checkpoint& c) { c.state.step = 50; }),
                  {"checkpoint.bin: state.step 50 is past the run's 10 steps"});
}

TEST_F(ForgedResume, ATimeThatIsNotTheStepsIsRefused) {
  expect_contains(resume_forged([](Checkpoint& c) { c.state.time += 0.001; }),
                  {"state.time", "is not the time of step 8"});
}

TEST_F(ForgedResume, AFrameThisRunDoesNotWriteIsRefused) {
  expect_contains(resume_forged([](Checkpoint& c) {
                    c.series.push_back({0.09, "frame_000009.vtu"});
                  }),
                  {"series entry frame_000009.vtu is not a frame this run writes"});
}

TEST_F(Resume, RefusesACheckpointWrittenWithoutTheAdaptiveModel) {
  write("young: 1.0e7", "adaptivity: {criteria: [{name: R_NL, threshold: 0.01}], ladder: [hooke, stvk]}\n");
  const auto refused = test_support::tensormass("run " + dir_.file("scene.yaml") + " --resume");
  EXPECT_EQ(refused.exit_code, 2);
  expect_contains(refused.output, {"was written for another version of"});
}

}  // namespace
}  // namespace tensormass
