// What the time steps of the 2D and the 3D engine share (step.cpp, step_3d.cpp,
// grid_update.cpp, grid_update_3d.cpp): what a step leaves, the grid rows a step touches, a
// stage's timer, and a plate's constraint on a node's normal velocity.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>

#include "compaction/params.hpp"

namespace compaction {

// What a step leaves: whether it closed the frame (the clock then stands on the frame's end)
// and why the state is unusable (empty when it is not).
struct StepOutcome {
  bool closes_frame = false;
  std::string problem;
};

// Only rows (y-layers in 3D) within reach of a particle can carry mass: the grid stages skip
// the others (the rows above a descending plate, most of them once the specimen is compacted).
// Grid: row_lo, row_hi, ny, gy, inv_dx; Measure: y_min, y_max of the particles.
template <typename Grid, typename Measure>
void select_active_rows(Grid& g, const Measure& m) {
  const int lo = static_cast<int>(std::floor(m.y_min * g.inv_dx + g.gy - 0.5));
  const int hi = static_cast<int>(std::floor(m.y_max * g.inv_dx + g.gy - 0.5)) + 3;
  g.row_lo = std::clamp(lo, 0, g.ny);
  g.row_hi = std::clamp(hi, g.row_lo, g.ny);
}

// Runs fn and adds its wall time to seconds.
template <typename Fn>
void timed(double& seconds, Fn&& fn) {
  const auto t0 = std::chrono::steady_clock::now();
  fn();
  seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The velocity a plate with normal velocity `plate` leaves a node with normal velocity `v`,
// for a plate that pushes in direction `push` (+1 pushes towards +y or +x, -1 towards -):
// bonded imposes the plate's velocity, unilateral only pushes.
inline double constrain(double v, double plate, double push, PlateContact contact) {
  if (contact == PlateContact::bonded) return plate;
  return push > 0 ? std::max(v, plate) : std::min(v, plate);
}

// The two plates on a node's normal velocity vy (the node of mass m at or beyond the bottom
// plate, at rest, or the top one, moving down at V): returns the constrained vy and adds each
// plate's change of the node's momentum, its reaction impulse, to bottom or top.
inline double apply_plates(double vy, double m, bool at_bottom, bool at_top, double V,
                           PlateContact contact, double& bottom, double& top) {
  if (at_bottom) {
    const double c = constrain(vy, 0.0, +1, contact);
    bottom += m * (c - vy);
    vy = c;
  }
  if (at_top) {
    const double c = constrain(vy, -V, -1, contact);
    top += m * (c - vy);
    vy = c;
  }
  return vy;
}

}  // namespace compaction
