// The 3D column's run loop: its stability checks (step and frame), cancellation, progress
// (its checkpoints: checkpoint_3d_gtest).
#include "compaction/simulation.hpp"
#include "stability_3d.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>

#include "scene_builder_3d.hpp"
#include "small_column_3d.hpp"

namespace compaction {
namespace {

SceneParams small_column() { return small_column_3d(); }

TEST(Simulation3dGtest, StepCheckNamesInversionSpeedAndLeavingTheGrid) {
  State3D s = build_scene_3d(small_column());
  EXPECT_EQ(check_step_3d(s), "");
  s.measure.bad_jacobian = true;
  EXPECT_NE(check_step_3d(s).find("inverted"), std::string::npos);
  s.measure.bad_jacobian = false;
  s.measure.max_v2 = std::nan("");
  EXPECT_NE(check_step_3d(s).find("P-wave"), std::string::npos);
  s.measure.max_v2 = 0.0;
  s.measure.y_min = -1.5 * s.grid.dx;  // beyond 1.4 cells below the bottom plate
  EXPECT_NE(check_step_3d(s).find("vertically"), std::string::npos);
}

TEST(Simulation3dGtest, FrameCheckNamesNonFiniteStressAndEnergyFromNowhere) {
  const State3D s = build_scene_3d(small_column());
  Frame f;
  EXPECT_EQ(check_frame_3d(s, f), "");
  f.sigma_top = std::nan("");
  EXPECT_NE(check_frame_3d(s, f).find("not finite"), std::string::npos);
  f.sigma_top = 0.0;
  const Particles3D& P = s.particles;
  f.kinetic_energy = 0.5 * P.mass * P.n * s.setup.V * s.setup.V;  // all of it moving at V
  f.plate_work = 0.1 * f.kinetic_energy;                          // with a tenth of the work
  EXPECT_NE(check_frame_3d(s, f).find("exceeds"), std::string::npos);
  f.plate_work = f.kinetic_energy;
  EXPECT_EQ(check_frame_3d(s, f), "");
}

TEST(Simulation3dGtest, ReportsProgressEveryFrameAndStopsWhenCancelled) {
  const SceneParams p = small_column();
  int frames = 0;
  RunControl control;
  control.on_progress = [&](const Progress& g) {
    ++frames;
    EXPECT_NEAR(g.eps, frames * p.d_eps, 1e-15);
  };
  const RunResult r = run_scene(p, control);
  ASSERT_EQ(r.status, RunStatus::ok) << r.reason;
  EXPECT_EQ(frames, 10);
  std::atomic<bool> cancel{true};
  RunControl stop;
  stop.cancel = &cancel;
  const RunResult c = run_scene(p, stop);
  EXPECT_EQ(c.status, RunStatus::cancelled);
  EXPECT_TRUE(c.frames.empty());
}

}  // namespace
}  // namespace compaction
