// run_scene: the scene of the parameters' geometry, driven by the one run loop (run_loop.hpp).
#include "compaction/simulation.hpp"

#include <chrono>
#include <stdexcept>

#include "column_2d.hpp"
#include "column_3d.hpp"
#include "run_loop.hpp"

namespace compaction {

RunResult run_scene(const SceneParams& p, const RunControl& control) {
  if (const auto errors = validate(p); !errors.empty()) {
    throw std::invalid_argument(errors[0].field + ": " + errors[0].message);
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (p.geometry == Geometry::pseudo1d_3d) {
    Column3D column(p, control);
    return run_loop(p, control, column, t0);
  }
  Column2D column(p, control);
  return run_loop(p, control, column, t0);
}

}  // namespace compaction
