// Builds the initial state of a 3D pseudo-1D column: the perforated specimen as particles, the
// grid around it.
#pragma once

#include "compaction/params.hpp"
#include "state_3d.hpp"

namespace compaction {

// The column: one unit cell of side L = h0 / n_rows across in x and z (periodic in both),
// n_rows cells tall, each with a centred cubic hole of side L (1 - phi)^(1/3) (phi = 1: none).
// Particles sit on a regular lattice of particles_per_cell^3 per grid cell; the hole is the
// particle count nearest its side, as in 2D (an odd count puts it half a particle off centre,
// the same in every cell). Bottom plate at y = 0, top plate at y = h0. The grid has
// p.grid_cells_per_unit() cells along a unit cell's side; p.geometry should be pseudo1d_3d, for
// which SceneParams gives the cubic hole's side and strut.
State3D build_scene_3d(const SceneParams& p);

}  // namespace compaction
