// The recipe of one time step of the 3D column, stage by stage (each stage in its own file),
// as step.cpp for 2D.
#include "step_3d.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "stages_3d.hpp"

namespace compaction {

namespace {

// Only y-layers within reach of a particle can carry mass: the grid stages skip the others
// (the layers above a descending plate).
void select_active_layers(State3D& s) {
  Grid3D& g = s.grid;
  const int lo = static_cast<int>(std::floor(s.measure.y_min * g.inv_dx + g.gy - 0.5));
  const int hi = static_cast<int>(std::floor(s.measure.y_max * g.inv_dx + g.gy - 0.5)) + 3;
  g.row_lo = std::clamp(lo, 0, g.ny);
  g.row_hi = std::clamp(hi, g.row_lo, g.ny);
}

template <typename Fn>
void timed(double& seconds, Fn&& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void advance_step_3d(State3D& s, double dt, StageTimes& times) {
  select_active_layers(s);                                   // 1. grid layers in use
  timed(times.p2g, [&] { p2g_3d(s, dt); });                  // 2. particles -> grid
  timed(times.grid_update, [&] { grid_update_3d(s); });      // 3. velocities, plates
  timed(times.g2p, [&] { g2p_3d(s, dt); });                  // 4. grid -> particles, F, tau
  s.clock.t += dt;
  ++s.clock.step;
}

}  // namespace compaction
