// The recipe of one time step of the 3D column, stage by stage (each stage in its own file),
// as step.cpp for 2D.
#include "step_3d.hpp"

#include "stability_3d.hpp"
#include "stages_3d.hpp"

namespace compaction {

StepOutcome advance_step_3d(State3D& s, double t_frame_end, double cfl, ThreadPool& pool,
                            StageTimes& times) {
  double dt = stable_dt_3d(s, cfl);                                // 1. CFL time step
  const bool closes_frame = s.clock.t + dt >= t_frame_end;         // 2. a frame ends on its
  if (closes_frame) dt = t_frame_end - s.clock.t;                  //    exact strain
  select_active_rows(s.grid, s.measure);                           // 3. grid layers in use
  timed(times.p2g, [&] { p2g_3d(s, dt, pool); });                  // 4. particles -> grid
  timed(times.grid_update, [&] { grid_update_3d(s, pool); });      // 5. velocities, plates
  timed(times.g2p, [&] { g2p_3d(s, dt, pool); });                  // 6. grid -> particles, F, tau
  s.clock.t = closes_frame ? t_frame_end : s.clock.t + dt;         // 7. the clock
  ++s.clock.step;
  return {closes_frame, check_step_3d(s)};                         // 8. stability
}

}  // namespace compaction
