// The small 3D column the engine's 3D tests run (simulation_3d_gtest, determinism_gtest,
// checkpoint_3d_gtest): 4 unit cells tall, 6 grid cells across, yielding (R = 1e-3 at S = 0.05)
// in its first frames; 10 frames, a fraction of a second.
#pragma once

#include "compaction/params.hpp"

namespace compaction {

inline SceneParams small_column_3d() {
  SceneParams p;
  p.geometry = Geometry::pseudo1d_3d;
  p.S = 0.05, p.R = 1e-3, p.phi = 0.5, p.n_rows = 4, p.cells_per_unit = 6, p.eps_end = 0.02;
  p.d_eps = 0.002, p.snapshot_eps = {}, p.movie_d_eps = 0.0;
  return p;
}

}  // namespace compaction
