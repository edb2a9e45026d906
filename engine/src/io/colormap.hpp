// Perceptually uniform colour map for the pictures of a bundle.
#pragma once

#include "png_image.hpp"

namespace compaction {

// Inferno-like map: t in [0, 1] (clamped; NaN maps to grey) to a colour, dark to bright.
Rgb inferno(double t);

}  // namespace compaction
