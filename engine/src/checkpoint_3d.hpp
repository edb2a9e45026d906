// Writing and restoring the 3D column's checkpoint (schema/checkpoint-format.md): the file and
// the sections of the 2D checkpoint (checkpoint_file.hpp) around the 3D particles.
#pragma once

#include <string>

#include "checkpoint_file.hpp"
#include "compaction/checkpoint.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "state_3d.hpp"

namespace compaction {

// As write_checkpoint (checkpoint.hpp), for the 3D column (no movie).
CheckpointInfo write_checkpoint_3d(const std::string& path, const SceneParams& p,
                                   const State3D& s, const RunResult& r, const RunPosition& at);

// As restore_checkpoint (checkpoint.hpp), over a state freshly built by build_scene_3d(p).
CheckpointInfo restore_checkpoint_3d(const std::string& path, const SceneParams& p, State3D& s,
                                     RunResult& r, RunPosition& at);

}  // namespace compaction
