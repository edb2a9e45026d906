// Early detection of numerical instability. A check returns the reason, or an empty string.
#pragma once

#include <string>

#include "compaction/result.hpp"
#include "state.hpp"

namespace compaction {

// After every step: inverted or non-finite deformation gradients, particle speeds at or above
// the P-wave speed (or NaN), particles leaving the grid (checked before any index is formed).
std::string check_step(const State& s);

// After every frame: kinetic energy beyond what the plates put in, non-finite stresses.
std::string check_frame(const State& s, const Frame& f);

}  // namespace compaction
