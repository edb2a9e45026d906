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

namespace {

// Layers [row_begin, row_end): velocities from momenta, then the plates.
PlateImpulses update_layers(State3D& s, int row_begin, int row_end) {
  Grid3D& g = s.grid;
  const Setup3D& su = s.setup;
  const double top = su.top_y(s.clock.t);
  const std::size_t layer = g.layer();
  double top_impulse = 0.0, bottom_impulse = 0.0;
  for (int j = row_begin; j < row_end; ++j) {
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
  return {.top = top_impulse, .bottom = bottom_impulse};
}

}  // namespace

// With threads, each updates a share of the layers; their impulses are added in thread order
// (thread 0's layers hold the bottom plate and the last thread's the top plate, so each impulse
// has the bits of one thread).
void grid_update_3d(State3D& s, ThreadPool& pool) {
  const Grid3D& g = s.grid;
  const std::size_t rows = static_cast<std::size_t>(g.row_hi - g.row_lo);
  pool.run([&](int t) {
    s.partial_impulses[t] = update_layers(s, g.row_lo + static_cast<int>(pool.begin(rows, t)),
                                          g.row_lo + static_cast<int>(pool.end(rows, t)));
  });
  PlateImpulses sum = s.partial_impulses[0];
  for (int t = 1; t < pool.size(); ++t) sum.top += s.partial_impulses[t].top, sum.bottom += s.partial_impulses[t].bottom;
  s.clock.top_impulse += sum.top;
  s.clock.bottom_impulse += sum.bottom;
  s.clock.plate_work += -s.setup.V * sum.top;  // the bottom plate does not move
}

}  // namespace compaction
