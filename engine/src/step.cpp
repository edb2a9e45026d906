// The recipe of one time step, stage by stage (each stage in its own file).
#include "step.hpp"

#include "stability.hpp"
#include "stages.hpp"

namespace compaction {

StepOutcome advance_step(State& s, double t_frame_end, double cfl, ThreadPool& pool,
                         StageTimes& times) {
  double dt = stable_dt(s, cfl);                                   // 1. CFL time step
  const bool closes_frame = s.clock.t + dt >= t_frame_end;         // 2. a frame ends on its
  if (closes_frame) dt = t_frame_end - s.clock.t;                  //    exact strain
  select_active_rows(s.grid, s.measure);                           // 3. grid rows in use
  timed(times.p2g, [&] { p2g(s, dt, pool); });                     // 4. particles -> grid
  timed(times.grid_update, [&] { grid_update(s, pool); });         // 5. velocities, plates, walls
  timed(times.g2p, [&] { g2p(s, dt, pool); });                     // 6. grid -> particles, F, tau
  s.clock.t = closes_frame ? t_frame_end : s.clock.t + dt;         // 7. the clock
  ++s.clock.step;
  return {closes_frame, check_step(s)};                            // 8. stability
}

}  // namespace compaction
