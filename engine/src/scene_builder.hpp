// Builds the initial state of a scene: the perforated specimen as particles, the grid around it.
#pragma once

#include "compaction/params.hpp"
#include "state.hpp"

namespace compaction {

// The specimen: n_cols x n_rows unit cells of side L = h0 / n_rows (pseudo1d: one column,
// periodic in x), each with a square hole: centred, of side L sqrt(1 - phi) in a regular
// structure; drawn from the seed in a random one (void_layout.hpp). Particles sit on a
// regular lattice of particles_per_cell^2 per grid cell, optionally perturbed by a seeded
// uniform offset of +-perturbation * spacing. Vertical struts (the solid between two holes of
// a row) are tagged for the buckling diagnostic.
State build_scene(const SceneParams& p);

}  // namespace compaction
