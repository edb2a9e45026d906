// Piecewise-linear interpolation through samples of matplotlib's "inferno" (CC0).
#include "colormap.hpp"

#include <cmath>

namespace compaction {

Rgb inferno(double t) {
  static constexpr unsigned char kStops[][3] = {
      {0, 0, 4},      {22, 11, 57},   {66, 10, 104},  {106, 23, 110}, {147, 38, 103},
      {188, 55, 84},  {221, 81, 58},  {243, 120, 25}, {252, 165, 10}, {246, 215, 70},
      {252, 255, 164}};
  constexpr int n = sizeof(kStops) / sizeof(kStops[0]);
  if (std::isnan(t)) return {128, 128, 128};
  t = t < 0 ? 0 : (t > 1 ? 1 : t);
  const double s = t * (n - 1);
  const int i = s >= n - 1 ? n - 2 : static_cast<int>(s);
  const double f = s - i;
  auto mix = [&](int c) {
    return static_cast<unsigned char>(std::lround(kStops[i][c] * (1 - f) + kStops[i + 1][c] * f));
  };
  return {mix(0), mix(1), mix(2)};
}

}  // namespace compaction
