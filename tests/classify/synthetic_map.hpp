// Synthetic space-time maps with analytic fronts, for the tracker tests.
#pragma once

#include <cmath>
#include <functional>
#include <vector>

#include "compaction/classify.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"

namespace compaction::classify::test {

// A pseudo-1D geometry of 34 unit cells, 10 rows per unit cell, frames every 0.002 of strain.
struct SyntheticRun {
  SceneParams params;
  RunResult result;
};

// rate(eps, y) gives the map's value at height y (units of h0) and strain eps; rows above the
// top plate (1 - eps) hold 0 as in the engine's map.
inline SyntheticRun make_run(double eps_end, const std::function<double(double, double)>& rate) {
  SyntheticRun s;
  s.params.cells_per_unit = 10;
  s.params.phi = 0.4;
  auto& r = s.result;
  r.phi_discrete = 0.4;
  const int rows = s.params.n_rows * s.params.cells_per_unit;
  const int frames = static_cast<int>(std::lround(eps_end / 0.002));
  r.spacetime.n_rows = rows;
  r.spacetime.n_frames = frames;
  r.spacetime.row_height = s.params.h0 / rows;
  r.spacetime.values.assign(static_cast<std::size_t>(rows) * frames, 0.0f);
  for (int f = 0; f < frames; ++f) {
    Frame fr;
    fr.eps = 0.002 * (f + 1);
    fr.sigma_top = fr.sigma_bottom = 100.0;
    fr.plastic_fraction = 0.5;
    r.frames.push_back(fr);
    for (int q = 0; q < rows; ++q) {
      const double y = (q + 0.5) / rows;
      if (y > 1.0 - fr.eps) continue;
      r.spacetime.values[static_cast<std::size_t>(f) * rows + q] = static_cast<float>(rate(fr.eps, y));
    }
  }
  r.eps_reached = 0.002 * frames;
  return s;
}

// A band of activity of peak 50 V/h0 and standard deviation half a unit cell around yc.
inline double bump(double y, double yc) {
  const double sigma = 0.5 / 34.0;
  return 50.0 * std::exp(-0.5 * (y - yc) * (y - yc) / (sigma * sigma));
}

// The features as classify() computes them: from the fronts and the band's path in the run's
// velocity map (an empty path when the run has none).
inline Features features_of(const SyntheticRun& s, const FrontTracks& t) {
  const BandPath band = follow_band(s.result.velocity, map_axes(s.params, s.result), TrackerSettings{});
  return compute_features(s.params, s.result, t, band);
}

}  // namespace compaction::classify::test
