// The 3D column's checkpoints (geometry pseudo1d_3d): a run stopped and resumed from its
// checkpoint ends with the bits of an uninterrupted run (frames, both maps, counts and the
// final particles: positions, velocities, C, Fe, tau, the open frame's plastic strain),
// whether it stopped at a frame's end or within a frame, on one thread or two; writing
// checkpoints changes nothing;
// a checkpoint of another scene (another S, or the 2D column's) is refused naming the key, a
// damaged or truncated one is refused. Exact: the resumed run must repeat the same
// floating-point operations on the same bits.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <string>

#include "checkpoint_checks.hpp"
#include "column_3d.hpp"
#include "compaction/checkpoint.hpp"
#include "compaction/simulation.hpp"
#include "run_loop.hpp"
#include "small_column_3d.hpp"

namespace compaction {
namespace {

using namespace checkpoint_checks;
using Checkpoint3dGtest = CheckpointFolder;

SceneParams small_column() { return small_column_3d(); }

// A run's result and the particles it ends with.
struct Ended {
  RunResult result;
  Particles3D particles;
};

Ended run_3d(const SceneParams& p, const RunControl& control) {
  Column3D column(p, control);
  Ended e;
  e.result = run_loop(p, control, column, std::chrono::steady_clock::now());
  e.particles = column.state().particles;
  return e;
}

bool same_matrices(const std::vector<Mat3>& a, const std::vector<Mat3>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k) {
    if (std::memcmp(a[k].data(), b[k].data(), sizeof(Mat3)) != 0) return false;
  }
  return true;
}

void expect_same_end(const Ended& a, const Ended& b) {
  expect_same_result(a.result, b.result);
  const Particles3D &x = a.particles, &y = b.particles;
  ASSERT_EQ(x.n, y.n);
  EXPECT_TRUE(x.x == y.x && x.y == y.y && x.z == y.z);
  EXPECT_TRUE(x.vx == y.vx && x.vy == y.vy && x.vz == y.vz);
  EXPECT_TRUE(same_matrices(x.C, y.C));
  EXPECT_TRUE(same_matrices(x.Fe, y.Fe));
  EXPECT_TRUE(same_matrices(x.tau, y.tau));
  EXPECT_TRUE(x.dep == y.dep);
}

Ended resume_to_end(const SceneParams& p, const std::string& resume) {
  RunControl c;
  c.resume_file = resume;
  return run_3d(p, c);
}

TEST_F(Checkpoint3dGtest, RunStoppedAtAFramesEndAndResumedGivesTheBitsOfAnUninterruptedRun) {
  const SceneParams p = small_column();
  const Ended whole = run_3d(p, {});
  ASSERT_EQ(whole.result.status, RunStatus::ok) << whole.result.reason;
  ASSERT_GT(whole.result.frames.back().plastic_fraction, 0.0);

  const RunResult first = run_until_frame(p, 4, "", path("a.ckpt"));
  ASSERT_EQ(first.status, RunStatus::cancelled);
  const CheckpointInfo at = read_checkpoint_info(path("a.ckpt"));
  EXPECT_EQ(at.frames, 4);
  EXPECT_EQ(at.step, first.steps);

  expect_same_end(whole, resume_to_end(p, path("a.ckpt")));
}

TEST_F(Checkpoint3dGtest, RunResumedFromWithinAFrameGivesTheBitsOfAnUninterruptedRun) {
  const SceneParams p = small_column();
  const Ended whole = run_3d(p, {});
  ASSERT_EQ(whole.result.status, RunStatus::ok) << whole.result.reason;

  // A checkpoint before every step; keep one taken within a frame, past yield.
  std::int64_t kept_step = -1;
  const RunControl c =
      keep_one_within_a_frame(path("every.ckpt"), path("mid.ckpt"), 0.011, kept_step);
  expect_same_end(whole, run_3d(p, c));  // writing checkpoints changes nothing
  ASSERT_GT(kept_step, 0);
  const CheckpointInfo mid = read_checkpoint_info(path("mid.ckpt"));
  EXPECT_EQ(mid.step, kept_step);
  EXPECT_GT(mid.eps, mid.frames * p.d_eps);  // within a frame

  expect_same_end(whole, resume_to_end(p, path("mid.ckpt")));
}

// On two threads (p2g_3d's shared layers summed in thread order): two runs give the same bits,
// and a run stopped at a frame's end and resumed gives them too.
TEST_F(Checkpoint3dGtest, OnTwoThreadsARunRepeatsItsBitsAndResumesWithThem) {
  SceneParams p = small_column();
  p.threads = 2;
  const Ended whole = run_3d(p, {});
  ASSERT_EQ(whole.result.status, RunStatus::ok) << whole.result.reason;
  ASSERT_GT(whole.result.frames.back().plastic_fraction, 0.0);
  expect_same_end(whole, run_3d(p, {}));
  const RunResult first = run_until_frame(p, 4, "", path("two.ckpt"));
  ASSERT_EQ(first.status, RunStatus::cancelled);
  expect_same_end(whole, resume_to_end(p, path("two.ckpt")));
}

TEST_F(Checkpoint3dGtest, CheckpointOfAnotherSceneIsRefusedNamingTheKey) {
  SceneParams p = small_column();
  run_until_frame(p, 1, "", path("a.ckpt"));
  p.S = 0.04;
  try {
    resume_to_end(p, path("a.ckpt"));
    FAIL() << "a checkpoint of another scene was resumed";
  } catch (const CheckpointRefused& e) {
    EXPECT_STREQ(e.what(), "the checkpoint is of another scene: S is 0.05 there and 0.04 here");
  }

  // the 2D column's checkpoint, taken before its first step
  SceneParams flat = small_column();
  flat.geometry = Geometry::pseudo1d;
  std::atomic<bool> cancel{true};
  RunControl c;
  c.cancel = &cancel;
  c.checkpoint_file = path("2d.ckpt");
  ASSERT_EQ(run_scene(flat, c).status, RunStatus::cancelled);
  try {
    resume_to_end(small_column(), path("2d.ckpt"));
    FAIL() << "a 2D checkpoint was resumed in 3D";
  } catch (const CheckpointRefused& e) {
    EXPECT_STREQ(e.what(), "the checkpoint is of another scene: geometry is \"pseudo1d\" there "
                           "and \"pseudo1d_3d\" here");
  }
}

TEST_F(Checkpoint3dGtest, DamagedOrTruncatedFilesAreRefused) {
  const SceneParams p = small_column();
  run_until_frame(p, 1, "", path("a.ckpt"));
  const std::string bytes = read_bytes(path("a.ckpt"));
  const auto refused_with = [&](const std::string& contents, const std::string& expected) {
    expect_refused([&](const std::string& file) { resume_to_end(p, file); }, path("bad.ckpt"),
                   contents, expected);
  };
  std::string flipped = bytes;
  flipped[bytes.size() / 2] ^= 0x01;  // one bit of a particle array
  refused_with(flipped, "checksum does not match");
  refused_with(bytes.substr(0, bytes.size() / 2), "checksum does not match");
  std::string truncated = bytes.substr(0, bytes.size() - 1000);
  truncated.append(4, '\0');
  reseal(truncated);  // a consistent checksum over sections that end early
  refused_with(truncated, "truncated");
}

}  // namespace
}  // namespace compaction
