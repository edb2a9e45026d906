// Runs one scene from its parameters to its result.
#pragma once

#include <atomic>
#include <functional>

#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "compaction/simd_copy.hpp"  // which compiled copy of the hot loops a scene runs

namespace compaction {

struct Progress {
  double eps = 0.0;        // imposed strain reached                      [-]
  double eps_end = 0.0;    // imposed strain the run stops at             [-]
  std::int64_t steps = 0;  // time steps taken
  double wall_seconds = 0.0;
};

struct RunControl {
  // Called after every frame (every d_eps of strain) from the thread that runs the scene.
  std::function<void(const Progress&)> on_progress;
  // When set and true, the run stops at the next step with status "cancelled".
  const std::atomic<bool>* cancel = nullptr;
};

// Runs the scene. Parameters must be valid (validate(p) empty), else std::invalid_argument.
// Never throws for numerical trouble: an unstable run returns status "unstable" with a reason.
RunResult run_scene(const SceneParams& p, const RunControl& control = {});

}  // namespace compaction
