// The recipe of one time step of the 3D column, stage by stage (each stage in its own file),
// as step.cpp for 2D.
#include "step_3d.hpp"

#include "stages_3d.hpp"
#include "step_helpers.hpp"

namespace compaction {

void advance_step_3d(State3D& s, double dt, StageTimes& times) {
  select_active_rows(s.grid, s.measure);                     // 1. grid layers in use
  timed(times.p2g, [&] { p2g_3d(s, dt); });                  // 2. particles -> grid
  timed(times.grid_update, [&] { grid_update_3d(s); });      // 3. velocities, plates
  timed(times.g2p, [&] { g2p_3d(s, dt); });                  // 4. grid -> particles, F, tau
  s.clock.t += dt;
  ++s.clock.step;
}

}  // namespace compaction
