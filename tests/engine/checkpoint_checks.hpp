// What the checkpoint tests of both geometries share (checkpoint_gtest, checkpoint_3d_gtest):
// a folder per test, the comparison of two results bit for bit, and the editing of a
// checkpoint's bytes.
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <unistd.h>

#include <atomic>
#include <functional>

#include "compaction/checkpoint.hpp"
#include "compaction/simulation.hpp"

namespace compaction::checkpoint_checks {

namespace fs = std::filesystem;

// A fresh folder per test, removed after it.
class CheckpointFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("checkpoint_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

inline void expect_same_maps(const SpaceTimeMap& a, const SpaceTimeMap& b) {
  EXPECT_EQ(a.n_rows, b.n_rows);
  EXPECT_EQ(a.n_frames, b.n_frames);
  EXPECT_EQ(a.row_height, b.row_height);
  EXPECT_TRUE(a.values == b.values);
}

// Every output bit but the wall times.
inline void expect_same_result(const RunResult& a, const RunResult& b) {
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.reason, b.reason);
  EXPECT_EQ(a.failed_step, b.failed_step);
  EXPECT_EQ(a.n_particles, b.n_particles);
  EXPECT_EQ(a.grid_nx, b.grid_nx);
  EXPECT_EQ(a.grid_ny, b.grid_ny);
  EXPECT_EQ(a.dx, b.dx);
  EXPECT_EQ(a.phi_discrete, b.phi_discrete);
  EXPECT_EQ(a.steps, b.steps);
  EXPECT_EQ(std::memcmp(&a.dt_mean, &b.dt_mean, sizeof(double)), 0);
  EXPECT_EQ(a.eps_reached, b.eps_reached);
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(std::memcmp(&a.frames[i], &b.frames[i], sizeof(Frame)), 0) << "frame " << i;
  }
  expect_same_maps(a.spacetime, b.spacetime);
  expect_same_maps(a.velocity, b.velocity);
  ASSERT_EQ(a.snapshots.size(), b.snapshots.size());
  for (std::size_t i = 0; i < a.snapshots.size(); ++i) {
    const Snapshot &x = a.snapshots[i], &y = b.snapshots[i];
    EXPECT_EQ(x.eps, y.eps);
    EXPECT_TRUE(x.x == y.x && x.y == y.y) << "snapshot " << i;
    EXPECT_TRUE(x.strain_rate == y.strain_rate && x.plastic_strain == y.plastic_strain &&
                x.jacobian == y.jacobian)
        << "snapshot " << i;
  }
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

inline void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// Sets the CRC-32 trailer of an edited checkpoint, so that only the edit is wrong.
inline void reseal(std::string& bytes) {
  const std::size_t end = bytes.size() - 4;
  const auto crc = static_cast<std::uint32_t>(
      crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(bytes.data()),
            static_cast<uInt>(end)));
  std::memcpy(bytes.data() + end, &crc, 4);
}

// Runs from `resume` (or from the start) until the frame `stop_after_frame` closes, when a
// cancel stops it and the runner writes its checkpoint to `checkpoint`.
inline RunResult run_until_frame(const SceneParams& p, int stop_after_frame,
                                 const std::string& resume, const std::string& checkpoint) {
  std::atomic<bool> cancel{false};
  RunControl c;
  c.cancel = &cancel;
  c.resume_file = resume;
  c.checkpoint_file = checkpoint;
  c.on_progress = [&](const Progress& pr) {
    if (pr.eps >= stop_after_frame * p.d_eps - 1e-12) cancel = true;
  };
  return run_scene(p, c);
}

// A control that writes a checkpoint to `every` before every step and copies to `keep` the
// first one taken past imposed strain `after_eps` after a step that did not close a frame
// (the frame's plastic increments and plate impulses are then partial); kept_step: its step.
inline RunControl keep_one_within_a_frame(const std::string& every, const std::string& keep,
                                          double after_eps, std::int64_t& kept_step) {
  RunControl c;
  c.checkpoint_file = every;
  c.checkpoint_every = 1e-12;
  kept_step = -1;
  c.on_checkpoint = [&kept_step, every, keep, after_eps,
                     last_frames = std::int64_t{-1}](const CheckpointInfo& info) mutable {
    if (kept_step < 0 && info.eps > after_eps && info.frames == last_frames) {
      fs::copy_file(every, keep);
      kept_step = info.step;
    }
    last_frames = info.frames;
  };
  return c;
}

// Expects `resume` of the checkpoint file `file`, written with `contents`, to be refused with
// a reason that contains `expected`.
inline void expect_refused(const std::function<void(const std::string&)>& resume,
                           const std::string& file, const std::string& contents,
                           const std::string& expected) {
  write_bytes(file, contents);
  try {
    resume(file);
    ADD_FAILURE() << "resumed a file that should be refused (" << expected << ")";
  } catch (const CheckpointRefused& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

}  // namespace compaction::checkpoint_checks
