// Grid update: momentum to velocity, then the rigid boundaries.
//
// Plates are frictionless and rigid: the bottom plate at y = 0 is fixed, the top plate at
// y = h0 - V t moves down at V. They act on the nodes at or beyond them, on the normal velocity
// only. "bonded" imposes the plate's velocity (the material cannot separate); "unilateral" only
// pushes (v_y >= 0 at the bottom, v_y <= -V at the top). Side walls (full2d) do the same in x.
// The change of momentum the plates impose is their reaction impulse on the material: the plate
// stress is that impulse per unit width and time, averaged over a frame (diagnostics.cpp).
// split_fields: a node with two fields is two nodes until it is full, then one
// (pore_contact.hpp).
// With threads, each updates a share of the rows and sums its plates' impulses apart; the
// shares are added in thread order. Thread 0's rows hold the bottom plate and the last
// thread's the top plate (a share is many rows), so each impulse has the bits of one thread.
#include <algorithm>

#include "stages.hpp"
#include "step_helpers.hpp"

namespace compaction {

namespace {

// Rows [row_begin, row_end): velocities from momenta, then the plates and walls.
PlateImpulses update_rows(State& s, int row_begin, int row_end) {
  Grid& g = s.grid;
  const Setup& su = s.setup;
  const bool flip = su.transfer == Transfer::pic_flip;
  const double top = s.clock.top_y(su);
  double top_impulse = 0.0, bottom_impulse = 0.0;
  Node* nodes = g.arrays.nodes.data();
  Node* second = su.split_fields ? nodes + g.field2 : nullptr;
  for (int j = row_begin; j < row_end; ++j) {
    const double y = (j - g.gy) * g.dx;
    const bool at_bottom = y <= 0.0, at_top = y >= top;
    // A node's velocity from its momentum, then the plates and walls on it.
    auto update = [&](Node& n, std::size_t k, int i) {
      const double inv_m = 1.0 / n.m;
      double vx = n.vx * inv_m, vy = n.vy * inv_m;
      if (flip) {  // v_old: the velocity before forces, for the FLIP increment
        g.arrays.mx[k] *= inv_m;
        g.arrays.my[k] *= inv_m;
      }
      vy = apply_plates(vy, n.m, at_bottom, at_top, su.V, su.contact, bottom_impulse, top_impulse);
      if (su.side_walls) {
        const double x = (i - g.gx) * g.dx;
        if (x <= 0.0) vx = constrain(vx, 0.0, +1, su.contact);
        if (x >= su.width) vx = constrain(vx, 0.0, -1, su.contact);
      }
      n.vx = vx;
      n.vy = vy;
    };
    for (int i = 0; i < g.nx; ++i) {
      const std::size_t k = static_cast<std::size_t>(j) * g.nx + i;
      Node& n = nodes[k];
      if (second != nullptr && second[k].m > 0.0) {  // split_fields (pore_contact.hpp)
        Node& n2 = second[k];
        if (n.m > 0.0 && n.m + n2.m < su.merge_mass) {  // a gap between them: two nodes
          update(n, k, i);
          update(n2, k, i);
          continue;
        }
        n.m += n2.m, n.vx += n2.vx, n.vy += n2.vy;  // full (or one field): one node
        update(n, k, i);
        n2.vx = n.vx, n2.vy = n.vy;
        continue;
      }
      if (n.m <= 0.0) continue;
      update(n, k, i);
    }
  }
  return {.top = top_impulse, .bottom = bottom_impulse};
}

}  // namespace

void grid_update(State& s, ThreadPool& pool) {
  const Grid& g = s.grid;
  const std::size_t rows = static_cast<std::size_t>(g.row_hi - g.row_lo);
  std::vector<PlateImpulses>& share = s.partial_impulses;  // sized once, one per thread
  pool.run([&](int t) {
    share[t] = update_rows(s, g.row_lo + static_cast<int>(pool.begin(rows, t)),
                           g.row_lo + static_cast<int>(pool.end(rows, t)));
  });
  PlateImpulses sum = share[0];
  for (int t = 1; t < pool.size(); ++t) sum.top += share[t].top, sum.bottom += share[t].bottom;
  s.clock.top_impulse += sum.top;
  s.clock.bottom_impulse += sum.bottom;
  s.clock.plate_work += -s.setup.V * sum.top;  // the bottom plate and the walls do not move
}

}  // namespace compaction
