// Writing and restoring a 2D run's checkpoint (schema/checkpoint-format.md): the state that
// determines the rest of the run, taken between two time steps. The file's framing and the
// sections every geometry shares: checkpoint_file.hpp; the 3D column's: checkpoint_3d.hpp.
#pragma once

#include <string>

#include "checkpoint_file.hpp"
#include "compaction/checkpoint.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "state.hpp"

namespace compaction {

// Writes the checkpoint to `path` atomically (a temporary file beside it, flushed, renamed over
// it), with the bytes of the movie file written so far when at.movie_frames > 0 (a resumed run
// may go on on another machine). Throws std::runtime_error on I/O errors; an earlier
// checkpoint at `path` then stays.
CheckpointInfo write_checkpoint(const std::string& path, const SceneParams& p, const State& s,
                                const RunResult& r, const RunPosition& at,
                                const std::string& movie_file = {});

// Restores a checkpoint over a state freshly built from the same scene (build_scene(p)) and its
// start result: particles, clock, step measures, the result so far and the loop's position.
// movie_bytes, when given, receives the movie file as it was (empty without a movie). Throws
// CheckpointRefused when the file is damaged or of another format, engine version or scene
// (threads aside), or when the built state does not match it.
CheckpointInfo restore_checkpoint(const std::string& path, const SceneParams& p, State& s,
                                  RunResult& r, RunPosition& at,
                                  std::string* movie_bytes = nullptr);

}  // namespace compaction
