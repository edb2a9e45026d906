// Checkpoints: a run stopped and resumed from its checkpoint ends with the bits of an
// uninterrupted run (every output: frames, both maps, snapshots, counts), whether it stopped
// at a frame's end or within a frame, once or twice; the movie of a run resumed in another
// folder (another machine) is the uninterrupted run's; a checkpoint of another scene, of another
// engine version, damaged or not a checkpoint at all is refused with a reason. Exact: the
// resumed run must repeat the same floating-point operations on the same bits.
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "checkpoint_checks.hpp"
#include "compaction/checkpoint.hpp"
#include "compaction/simulation.hpp"

namespace compaction {
namespace {

// Small, with a perturbation (the seeded offsets are restored, not rebuilt) and two snapshots,
// one before and one after the stops below. 10 frames, a few hundred steps.
SceneParams small_scene() {
  SceneParams p;
  p.S = 0.05, p.R = 1e-3, p.phi = 0.4, p.cells_per_unit = 6, p.eps_end = 0.02;
  p.perturbation = 0.05, p.seed = 7, p.snapshot_eps = {0.005, 0.015};
  return p;
}

using namespace checkpoint_checks;
using CheckpointGtest = CheckpointFolder;

RunResult resume_to_end(const SceneParams& p, const std::string& resume) {
  RunControl c;
  c.resume_file = resume;
  return run_scene(p, c);
}

TEST_F(CheckpointGtest, RunStoppedTwiceAndResumedGivesTheBitsOfAnUninterruptedRun) {
  const SceneParams p = small_scene();
  const RunResult whole = run_scene(p);
  ASSERT_EQ(whole.status, RunStatus::ok) << whole.reason;
  ASSERT_EQ(whole.snapshots.size(), 2u);

  const RunResult first = run_until_frame(p, 3, "", path("a.ckpt"));
  ASSERT_EQ(first.status, RunStatus::cancelled);
  const CheckpointInfo at_a = read_checkpoint_info(path("a.ckpt"));
  EXPECT_EQ(at_a.frames, 3);
  EXPECT_EQ(at_a.step, first.steps);
  EXPECT_EQ(at_a.engine_version, engine_version());

  const RunResult second = run_until_frame(p, 6, path("a.ckpt"), path("b.ckpt"));
  ASSERT_EQ(second.status, RunStatus::cancelled);
  EXPECT_EQ(read_checkpoint_info(path("b.ckpt")).frames, 6);
  EXPECT_EQ(second.snapshots.size(), 1u);  // the one at 0.005, restored from a.ckpt

  expect_same_result(whole, resume_to_end(p, path("b.ckpt")));
}

// Two velocity fields carry the particles' face normals: a checkpoint keeps them (restoring the
// scene's initial normals instead changes the bits after the resume).
TEST_F(CheckpointGtest, SplitFieldsRunResumedGivesTheBitsOfAnUninterruptedRun) {
  SceneParams p = small_scene();
  p.cells_per_unit = 14, p.eps_end = 0.01, p.snapshot_eps = {0.005};  // 3.2 cells across the strut
  p.pore_contact = PoreContact::split_fields;
  ASSERT_TRUE(validate(p).empty());
  const RunResult whole = run_scene(p);
  ASSERT_EQ(whole.status, RunStatus::ok) << whole.reason;
  const RunResult first = run_until_frame(p, 3, "", path("a.ckpt"));
  ASSERT_EQ(first.status, RunStatus::cancelled);
  expect_same_result(whole, resume_to_end(p, path("a.ckpt")));
}

TEST_F(CheckpointGtest, RunResumedFromWithinAFrameGivesTheBitsOfAnUninterruptedRun) {
  const SceneParams p = small_scene();
  const RunResult whole = run_scene(p);
  ASSERT_EQ(whole.status, RunStatus::ok) << whole.reason;

  // A checkpoint before every step; keep one taken within a frame, past the first snapshot.
  std::int64_t kept_step = -1;
  const RunControl c =
      keep_one_within_a_frame(path("every.ckpt"), path("mid.ckpt"), 0.007, kept_step);
  expect_same_result(whole, run_scene(p, c));  // writing checkpoints changes nothing
  ASSERT_GT(kept_step, 0);
  const CheckpointInfo mid = read_checkpoint_info(path("mid.ckpt"));
  EXPECT_EQ(mid.step, kept_step);
  EXPECT_GT(mid.eps, mid.frames * p.d_eps);  // within a frame

  expect_same_result(whole, resume_to_end(p, path("mid.ckpt")));
}

TEST_F(CheckpointGtest, AMovieResumedInAnotherFolderIsTheUninterruptedRunsMovie) {
  SceneParams p = small_scene();
  p.movie_d_eps = 0.004;  // frames at 0.004, 0.008, ...: two before the stop, three after
  RunControl whole;
  whole.movie_file = path("whole.bin");
  ASSERT_EQ(run_scene(p, whole).status, RunStatus::ok);

  std::atomic<bool> cancel{false};
  RunControl first;
  first.cancel = &cancel;
  first.checkpoint_file = path("a.ckpt");
  first.movie_file = path("first.bin");
  first.on_progress = [&](const Progress& pr) {
    if (pr.eps >= 5 * p.d_eps - 1e-12) cancel = true;
  };
  ASSERT_EQ(run_scene(p, first).status, RunStatus::cancelled);

  // another machine: the first session's movie file is not there
  RunControl second;
  second.resume_file = path("a.ckpt");
  second.movie_file = path("elsewhere.bin");
  ASSERT_EQ(run_scene(p, second).status, RunStatus::ok);
  const std::string a = read_bytes(path("whole.bin")), b = read_bytes(path("elsewhere.bin"));
  EXPECT_GT(a.size(), 96u);
  EXPECT_TRUE(a == b) << a.size() << " bytes against " << b.size();
}

TEST_F(CheckpointGtest, CheckpointOfAnotherSceneIsRefusedNamingTheField) {
  SceneParams p = small_scene();
  run_until_frame(p, 2, "", path("a.ckpt"));
  p.S = 0.04;
  try {
    resume_to_end(p, path("a.ckpt"));
    FAIL() << "a checkpoint of another scene was resumed";
  } catch (const CheckpointRefused& e) {
    EXPECT_STREQ(e.what(), "the checkpoint is of another scene: S is 0.05 there and 0.04 here");
  }
  p = small_scene();
  p.threads = 2;  // the thread count is not part of the scene's identity
  EXPECT_EQ(resume_to_end(p, path("a.ckpt")).status, RunStatus::ok);
}

TEST_F(CheckpointGtest, CheckpointOfAnotherEngineVersionIsRefused) {
  const SceneParams p = small_scene();
  run_until_frame(p, 2, "", path("a.ckpt"));
  std::string bytes = read_bytes(path("a.ckpt"));
  const std::string ours = std::string("\"engine_version\":\"") + engine_version() + "\"";
  const std::size_t at = bytes.find(ours);
  ASSERT_NE(at, std::string::npos);
  std::string other = ours;
  other[other.size() - 2] = other[other.size() - 2] == '9' ? '8' : '9';  // last digit
  bytes.replace(at, ours.size(), other);
  reseal(bytes);
  write_bytes(path("other.ckpt"), bytes);
  try {
    resume_to_end(p, path("other.ckpt"));
    FAIL() << "a checkpoint of another engine version was resumed";
  } catch (const CheckpointRefused& e) {
    EXPECT_NE(std::string(e.what()).find("the checkpoint was written by engine "),
              std::string::npos)
        << e.what();
  }
}

TEST_F(CheckpointGtest, DamagedTruncatedOrForeignFilesAreRefused) {
  const SceneParams p = small_scene();
  run_until_frame(p, 2, "", path("a.ckpt"));
  const std::string bytes = read_bytes(path("a.ckpt"));
  const auto refused_with = [&](const std::string& contents, const std::string& expected) {
    expect_refused([&](const std::string& file) { resume_to_end(p, file); }, path("bad.ckpt"),
                   contents, expected);
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x01;  // one bit of a particle array
  refused_with(flipped, "checksum does not match");
  refused_with(bytes.substr(0, bytes.size() / 2), "checksum does not match");
  refused_with("{\"S\": 0.05}", "is not a compaction checkpoint");
  std::string truncated = bytes.substr(0, bytes.size() - 1000);
  truncated.append(4, '\0');
  reseal(truncated);  // a consistent checksum over sections that end early
  refused_with(truncated, "truncated");
}

}  // namespace
}  // namespace compaction
