// A scene that blows up ends "unstable" with a reason and stores no NaN or Inf; it never
// crashes or hangs. Cancellation stops a run cleanly.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "compaction/simulation.hpp"

namespace compaction {
namespace {

void expect_all_finite(const RunResult& r) {
  for (const Frame& f : r.frames) {
    for (double v : {f.eps, f.sigma_top, f.sigma_bottom, f.kinetic_energy, f.plate_work,
                     f.max_deflection, f.max_speed}) {
      ASSERT_TRUE(std::isfinite(v));
    }
  }
  for (float v : r.spacetime.values) ASSERT_TRUE(std::isfinite(v));
  for (const Snapshot& s : r.snapshots) {
    for (float v : s.x) ASSERT_TRUE(std::isfinite(v));
    for (float v : s.jacobian) ASSERT_TRUE(std::isfinite(v));
  }
  EXPECT_EQ(r.spacetime.values.size(),
            static_cast<std::size_t>(r.spacetime.n_frames) * r.spacetime.n_rows);
}

TEST(StabilityGtest, AbsurdCflEndsUnstableWithAReasonAndNoNan) {
  SceneParams p;
  p.S = 0.01, p.R = 1e-3, p.cells_per_unit = 6, p.eps_end = 0.05, p.cfl = 1.9;
  const RunResult r = run_scene(p);
  EXPECT_EQ(r.status, RunStatus::unstable);
  EXPECT_FALSE(r.reason.empty());
  EXPECT_GT(r.failed_step, 0);
  EXPECT_LT(r.eps_reached, p.eps_final());
  expect_all_finite(r);
}

TEST(StabilityGtest, HealthyRunPassesEveryCheck) {
  SceneParams p;
  p.S = 0.05, p.R = 1e-3, p.cells_per_unit = 6, p.eps_end = 0.03;
  const RunResult r = run_scene(p);
  EXPECT_EQ(r.status, RunStatus::ok) << r.reason;
  EXPECT_NEAR(r.eps_reached, 0.03, 1e-12);
  EXPECT_EQ(r.frames.size(), 15u);
  expect_all_finite(r);
}

TEST(StabilityGtest, CancelStopsTheRun) {
  SceneParams p;
  p.S = 0.05, p.R = 1e-3, p.cells_per_unit = 6, p.eps_end = 0.5;
  std::atomic<bool> cancel{false};
  RunControl control;
  control.cancel = &cancel;
  control.on_progress = [&](const Progress& pr) {
    if (pr.eps >= 0.01) cancel = true;
  };
  const RunResult r = run_scene(p, control);
  EXPECT_EQ(r.status, RunStatus::cancelled);
  EXPECT_LT(r.eps_reached, 0.02);
}

}  // namespace
}  // namespace compaction
