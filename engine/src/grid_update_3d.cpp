// Grid update of the 3D column: momentum to velocity, then the rigid plates, as 2D's
// grid_update.cpp. The plates are frictionless: the bottom one at y = 0 fixed, the top one at
// y = h0 - V t moving down at V; they act on the normal velocity (y) of the nodes at or beyond
// them, "bonded" imposing the plate's velocity, "unilateral" only pushing. The change of
// momentum they impose is their reaction impulse on the material. x and z are periodic: no
// walls.
#include <algorithm>

#include "stages_3d.hpp"
#include "step_helpers.hpp"

namespace compaction {

void grid_update_3d(State3D& s) {
  Grid3D& g = s.grid;
  const Setup3D& su = s.setup;
  const double top = su.top_y(s.clock.t);
  const std::size_t layer = g.layer();
  double top_impulse = 0.0, bottom_impulse = 0.0;
  for (int j = g.row_lo; j < g.row_hi; ++j) {
    const double y = (j - g.gy) * g.dx;
    const bool at_bottom = y <= 0.0, at_top = y >= top;
    Node3D* row = g.nodes.data() + static_cast<std::size_t>(j) * layer;
    for (std::size_t k = 0; k < layer; ++k) {
      Node3D& n = row[k];
      if (n.m <= 0.0) continue;
      const double inv_m = 1.0 / n.m;
      const double vy = apply_plates(n.vy * inv_m, n.m, at_bottom, at_top, su.V, su.contact,
                                     bottom_impulse, top_impulse);
      n.vx *= inv_m;
      n.vy = vy;
      n.vz *= inv_m;
    }
  }
  s.clock.top_impulse += top_impulse;
  s.clock.bottom_impulse += bottom_impulse;
  s.clock.plate_work += -su.V * top_impulse;  // the bottom plate does not move
}

}  // namespace compaction
