// Runs one scene from its parameters to its result.
#pragma once

#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "compaction/run_control.hpp"
#include "compaction/simd_copy.hpp"  // which compiled copy of the hot loops a scene runs

namespace compaction {

// Runs the scene. Parameters must be valid (validate(p) empty), else std::invalid_argument.
// A checkpoint that cannot be written throws std::runtime_error; one that cannot be resumed
// throws CheckpointRefused.
// Never throws for numerical trouble: an unstable run returns status "unstable" with a reason.
RunResult run_scene(const SceneParams& p, const RunControl& control = {});

}  // namespace compaction
