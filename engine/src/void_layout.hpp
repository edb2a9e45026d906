// The voids of the specimen on the particle lattice: one square void per unit cell, centred
// and alike in a regular structure, drawn from the seed in a random one (random_structure in
// params.hpp states the distribution).
#pragma once

#include <vector>

#include "compaction/params.hpp"

namespace compaction {

// A void: particle columns [x0, x1) and rows [y0, y1) within its unit cell (0 .. per_unit).
struct Void {
  int x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  bool empty() const { return x1 <= x0 || y1 <= y0; }
};

struct VoidLayout {
  int cols = 0, rows = 0;    // unit cells across and along the specimen
  std::vector<Void> voids;   // voids[cy * cols + cx]
  const Void& at(int cx, int cy) const { return voids[static_cast<std::size_t>(cy) * cols + cx]; }
};

// The voids of scene `p` with `per_unit` particles along a unit cell's side.
// Regular: the side is the particle count nearest L sqrt(1 - phi), starting at
// (per_unit - side) / 2 in every cell. Random: areas in antithetic pairs dealt in a seeded order, sides rounded to the
// lattice, each void placed uniformly among the lattice positions that keep
// round(kMinStrut * regular strut / 2) particles (at least one) to its cell's edges.
VoidLayout void_layout(const SceneParams& p, int per_unit);

}  // namespace compaction
