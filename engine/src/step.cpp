// The recipe of one time step, stage by stage (each stage in its own file).
#include "step.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "stages.hpp"

namespace compaction {

namespace {

// Only rows within reach of a particle can carry mass: the grid stages skip the others (the
// rows above a descending plate, most of them once the specimen is compacted).
void select_active_rows(State& s) {
  Grid& g = s.grid;
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

void advance_step(State& s, double dt, ThreadPool& pool, StageTimes& times) {
  select_active_rows(s);                                         // 1. grid rows in use
  timed(times.p2g, [&] { p2g(s, dt, pool); });                   // 2. particles -> grid
  timed(times.grid_update, [&] { grid_update(s); });             // 3. velocities, plates, walls
  timed(times.g2p, [&] { g2p(s, dt, pool); });                   // 4. grid -> particles, F, tau
  s.clock.t += dt;
  ++s.clock.step;
}

}  // namespace compaction
