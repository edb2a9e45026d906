// The recipe of one time step, stage by stage (each stage in its own file).
#include "step.hpp"

#include "stages.hpp"
#include "step_helpers.hpp"

namespace compaction {

void advance_step(State& s, double dt, ThreadPool& pool, StageTimes& times) {
  select_active_rows(s.grid, s.measure);                         // 1. grid rows in use
  timed(times.p2g, [&] { p2g(s, dt, pool); });                   // 2. particles -> grid
  timed(times.grid_update, [&] { grid_update(s, pool); });       // 3. velocities, plates, walls
  timed(times.g2p, [&] { g2p(s, dt, pool); });                   // 4. grid -> particles, F, tau
  s.clock.t += dt;
  ++s.clock.step;
}

}  // namespace compaction
