// The movie (compaction/movie.hpp, schema/movie-format.md): written during a run frame by frame
// at every movie_d_eps, the same particles as the snapshots to the quantisation, the same bits
// for the same scene, listed in summary.json, validated, and resumable from a frame count.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "compaction/bundle.hpp"
#include "compaction/movie.hpp"
#include "compaction/simulation.hpp"
#include "movie_recorder.hpp"
#include "scene_builder.hpp"

namespace compaction {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string bytes_of(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// A small scene: 5 cells per unit cell, to eps = 0.04, frames every 0.002, movie every 0.01.
SceneParams small_scene() {
  SceneParams p;
  p.S = 0.05, p.R = 1e-3, p.cells_per_unit = 5, p.eps_end = 0.04;
  p.snapshot_eps = {0.02, 0.04};
  p.movie_d_eps = 0.01;
  return p;
}

RunResult run_with_movie(const SceneParams& p, const fs::path& file) {
  RunControl c;
  c.movie_file = file.string();
  return run_scene(p, c);
}

TEST(MovieGtest, FramesFallOnEachMultipleAndMatchTheSnapshots) {
  const SceneParams p = small_scene();
  const fs::path dir = temp_dir("movie_gtest_frames");
  const RunResult r = run_with_movie(p, dir / "movie.bin");
  ASSERT_EQ(r.status, RunStatus::ok);
  const movie::Movie m = movie::read(dir / "movie.bin");
  ASSERT_EQ(m.header.n_particles, static_cast<std::uint64_t>(r.n_particles));
  ASSERT_EQ(m.frames.size(), 4u);
  EXPECT_EQ(movie::frame_count(p), 4u);
  EXPECT_EQ(fs::file_size(dir / "movie.bin"),
            movie::kHeaderBytes + 4 * movie::frame_bytes(r.n_particles));
  EXPECT_EQ(movie::frame_bytes(r.n_particles) % 8, 0u);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(m.frames[k].eps, 0.01 * (k + 1), 1e-12);
  EXPECT_EQ(m.header.flags, movie::kPeriodicX);  // pseudo-1D
  EXPECT_DOUBLE_EQ(m.header.x_hi, p.width());
  EXPECT_DOUBLE_EQ(m.header.y_hi, p.h0);

  // Frames 1 and 3 are at the snapshots' strains: the same particles, positions to half a
  // quantum (plus the snapshot's float rounding), rates to one level (a level boundary may
  // fall between the float snapshot and the double the recorder quantises).
  ASSERT_EQ(r.snapshots.size(), 2u);
  for (int s = 0; s < 2; ++s) {
    const Snapshot& snap = r.snapshots[s];
    const movie::Frame& f = m.frames[2 * s + 1];
    ASSERT_NEAR(f.eps, snap.eps, 1e-12);
    const double qx = p.width() / 65535, qy = p.h0 / 65535;
    int moving = 0;
    for (std::size_t i = 0; i < snap.x.size(); ++i) {
      ASSERT_NEAR(f.x[i], snap.x[i], 0.5 * qx + 1e-6 * p.width()) << i;
      ASSERT_NEAR(f.y[i], snap.y[i], 0.5 * qy + 1e-6 * p.h0) << i;
      ASSERT_LE(std::abs(int{f.level[i]} - int{movie::rate_level(snap.strain_rate[i])}), 1) << i;
      moving += f.level[i] > 0;
    }
    EXPECT_GT(moving, 0) << "some particles flow by eps = " << snap.eps;
  }
  fs::remove_all(dir);
}

TEST(MovieGtest, SameSceneSameBits) {
  const SceneParams p = small_scene();
  const fs::path dir = temp_dir("movie_gtest_bits");
  run_with_movie(p, dir / "a.bin");
  run_with_movie(p, dir / "b.bin");
  EXPECT_EQ(bytes_of(dir / "a.bin"), bytes_of(dir / "b.bin"));
  fs::remove_all(dir);
}

TEST(MovieGtest, SummaryListsTheMovieTheRunWrote) {
  SceneParams p = small_scene();
  const fs::path dir = temp_dir("movie_gtest_summary");
  const RunResult r = run_with_movie(p, dir / movie::kFileName);
  write_bundle(dir, p, r);
  const Bundle b = read_bundle(dir);
  ASSERT_TRUE(b.summary.contains("movie"));
  EXPECT_EQ(b.summary["movie"]["file"], "movie.bin");
  EXPECT_EQ(b.summary["movie"]["frames"], 4);
  EXPECT_EQ(b.summary["movie"]["n_particles"], r.n_particles);
  EXPECT_EQ(b.params.movie_d_eps, 0.01);

  // Without a movie the run writes no file and the summary lists none.
  p.movie_d_eps = 0.0;
  const fs::path none = temp_dir("movie_gtest_none");
  write_bundle(none, p, run_with_movie(p, none / movie::kFileName));
  EXPECT_FALSE(fs::exists(none / movie::kFileName));
  EXPECT_FALSE(read_bundle(none).summary.contains("movie"));
  fs::remove_all(dir);
  fs::remove_all(none);
}

TEST(MovieGtest, IntervalIsValidated) {
  SceneParams p;
  p.movie_d_eps = 0.001;  // in range, below d_eps = 0.002
  auto errors = validate(p);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "movie_d_eps");
  EXPECT_NE(errors[0].message.find("d_eps"), std::string::npos) << errors[0].message;
  p.movie_d_eps = 0.6;  // above the range
  errors = validate(p);
  ASSERT_EQ(errors.size(), 1u);
  EXPECT_EQ(errors[0].field, "movie_d_eps");
  p.movie_d_eps = -0.01;
  EXPECT_EQ(validate(p).size(), 1u);
  p.movie_d_eps = 0.0;  // no movie
  EXPECT_TRUE(validate(p).empty());
  p.movie_d_eps = 0.002;  // every frame
  EXPECT_TRUE(validate(p).empty());
}

TEST(MovieGtest, BundleBoundCountsTheMovie) {
  SceneParams p;  // the default scene: 30 frames of about 21 800 particles
  const std::size_t with = bundle_size_bound(p);
  EXPECT_GE(movie_size_bound(p), movie::kHeaderBytes + 30 * movie::frame_bytes(21760));
  p.movie_d_eps = 0.0;
  EXPECT_EQ(movie_size_bound(p), 0u);
  EXPECT_EQ(with - bundle_size_bound(p), movie_size_bound(SceneParams{}));
}

TEST(MovieGtest, ResumeKeepsTheFramesWrittenAndGoesOn) {
  const SceneParams p = small_scene();
  const fs::path dir = temp_dir("movie_gtest_resume");
  run_with_movie(p, dir / "movie.bin");
  const std::string whole = bytes_of(dir / "movie.bin");
  const std::size_t fb = movie::frame_bytes(movie::read_header(dir / "movie.bin").n_particles);

  // A recorder that goes on after frame 2 of 4 keeps those two and writes the third where it was.
  State s = build_scene(p);
  MovieRecorder rec((dir / "movie.bin").string(), p, s);
  rec.resume(2);
  EXPECT_EQ(rec.frames_written(), 2);
  EXPECT_EQ(movie::read_header(dir / "movie.bin").n_frames, 2u);
  EXPECT_EQ(bytes_of(dir / "movie.bin"), whole.substr(0, movie::kHeaderBytes + 2 * fb).replace(24, 8, std::string("\x02\0\0\0\0\0\0\0", 8)));
  rec.record_if_due(s.particles, 0.025, 0.002);  // not yet due: frame 3 is at 0.03
  EXPECT_EQ(rec.frames_written(), 2);
  rec.record_if_due(s.particles, 0.03, 0.002);
  EXPECT_EQ(rec.frames_written(), 3);
  const movie::Movie m = movie::read(dir / "movie.bin");
  ASSERT_EQ(m.frames.size(), 3u);
  EXPECT_NEAR(m.frames[2].eps, 0.03, 1e-15);
  EXPECT_EQ(bytes_of(dir / "movie.bin").substr(movie::kHeaderBytes, 2 * fb),
            whole.substr(movie::kHeaderBytes, 2 * fb));

  // Another scene's file, or one with fewer frames, is refused.
  SceneParams other = p;
  other.movie_d_eps = 0.02;
  MovieRecorder wrong((dir / "movie.bin").string(), other, s);
  EXPECT_THROW(wrong.resume(2), std::runtime_error);
  MovieRecorder longer((dir / "movie.bin").string(), p, s);
  EXPECT_THROW(longer.resume(5), std::runtime_error);
  fs::remove_all(dir);
}

TEST(MovieGtest, MalformedFilesAreRefusedByName) {
  const fs::path dir = temp_dir("movie_gtest_bad");
  std::ofstream(dir / "movie.bin", std::ios::binary) << "not a movie";
  try {
    movie::read(dir / "movie.bin");
    FAIL() << "read a malformed movie";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("movie.bin"), std::string::npos) << e.what();
  }
  EXPECT_THROW(movie::read(dir / "absent.bin"), std::runtime_error);
  fs::remove_all(dir);
}

TEST(MovieGtest, RateLevelsRoundTrip) {
  EXPECT_EQ(movie::rate_level(0.0), 0);
  EXPECT_EQ(movie::rate_level(-1.0), 0);
  EXPECT_EQ(movie::rate_level(std::nan("")), 0);
  EXPECT_EQ(movie::rate_level(1e9), 255);
  for (double v : {0.5, 3.0, 40.0, 700.0}) {
    const double back = movie::rate_of_level(movie::rate_level(v));
    // half a level: 2/255 decades of 1 + rate
    EXPECT_NEAR(std::log10(1 + back), std::log10(1 + v), 0.5 * movie::kRateLog10Max / 255 + 1e-12) << v;
  }
}

}  // namespace
}  // namespace compaction
