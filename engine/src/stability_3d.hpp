// Early detection of numerical instability in the 3D column, as stability.hpp's in 2D. A check
// returns the reason, or an empty string.
#pragma once

#include <string>

#include "compaction/result.hpp"
#include "state_3d.hpp"

namespace compaction {

// After every step: an inverted or non-finite Fe, a particle as fast as the P-wave, a particle
// within 1.4 cells of the grid's top or bottom edge (its stencil would leave the grid).
std::string check_step_3d(const State3D& s);

// After every frame: a non-finite plate stress or kinetic energy, or kinetic energy above twice
// the plates' work plus 1 % of that of the whole specimen moving at V.
std::string check_frame_3d(const State3D& s, const Frame& f);

}  // namespace compaction
