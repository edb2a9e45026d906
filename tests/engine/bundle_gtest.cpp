// The result bundle: written, read back equal, files in their documented formats.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "compaction/bundle.hpp"
#include "compaction/simulation.hpp"

namespace compaction {
namespace {

namespace fs = std::filesystem;

std::string head(const fs::path& p, std::size_t n) {
  std::ifstream f(p, std::ios::binary);
  std::string s(n, '\0');
  f.read(s.data(), static_cast<std::streamsize>(n));
  return s;
}

TEST(BundleGtest, WrittenBundleReadsBackEqual) {
  SceneParams p;
  p.S = 0.05, p.R = 1e-3, p.cells_per_unit = 6, p.eps_end = 0.02, p.snapshot_eps = {0.01};
  const RunResult r = run_scene(p);
  const fs::path dir = fs::temp_directory_path() / ("bundle_gtest_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  write_bundle(dir, p, r);

  for (const char* f : {"summary.json", "frames.csv", "spacetime.npy", "spacetime.png",
                        "velocity.npy", "snapshot_0.010.npy", "snapshot_0.010.png"}) {
    EXPECT_TRUE(fs::exists(dir / f)) << f;
  }
  EXPECT_EQ(head(dir / "spacetime.png", 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(head(dir / "spacetime.npy", 6), std::string("\x93NUMPY", 6));

  const Bundle b = read_bundle(dir);
  EXPECT_EQ(b.summary.at("engine_version"), engine_version());
  EXPECT_EQ(b.summary.at("status"), "ok");
  // Both measures of the resolution: the override asked for and what it gives across a strut.
  EXPECT_EQ(b.summary.at("params").at("cells_per_unit"), 6);
  EXPECT_EQ(b.summary.at("grid").at("cells_per_unit"), 6);
  EXPECT_DOUBLE_EQ(b.summary.at("grid").at("cells_per_strut").get<double>(),
                   6 * (1 - std::sqrt(1 - p.phi)));
  EXPECT_EQ(b.result.n_particles, r.n_particles);
  EXPECT_EQ(b.result.steps, r.steps);
  EXPECT_EQ(b.result.spacetime.values, r.spacetime.values);  // float32 stored exactly
  ASSERT_EQ(r.velocity.n_frames, r.spacetime.n_frames);
  EXPECT_EQ(b.result.velocity.n_rows, r.spacetime.n_rows);
  EXPECT_EQ(b.result.velocity.values, r.velocity.values);
  ASSERT_EQ(b.result.frames.size(), r.frames.size());
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    EXPECT_NEAR(b.result.frames[i].sigma_top, r.frames[i].sigma_top,
                1e-8 * std::abs(r.frames[i].sigma_top) + 1e-300);  // printed with 9 digits
  }
  ASSERT_EQ(b.result.snapshots.size(), 1u);
  EXPECT_EQ(b.result.snapshots[0].x.size(), static_cast<std::size_t>(r.n_particles));
  EXPECT_EQ(b.result.snapshots[0].jacobian, r.snapshots[0].jacobian);
  fs::remove_all(dir);
}

TEST(BundleGtest, MissingFileIsNamedInTheError) {
  const fs::path dir = fs::temp_directory_path() / "bundle_gtest_missing";
  fs::create_directories(dir);
  try {
    read_bundle(dir);
    FAIL() << "expected an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("summary.json"), std::string::npos);
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace compaction
