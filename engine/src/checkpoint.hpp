// Writing and restoring a run's checkpoint (schema/checkpoint-format.md): the state that
// determines the rest of the run, taken between two time steps.
#pragma once

#include <cstdint>
#include <string>

#include "compaction/checkpoint.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "state.hpp"

namespace compaction {

// Where the run loop stands between two steps, besides the state and the result so far.
struct RunPosition {
  std::int64_t frame = 0;         // frames closed
  double eps_frame_begin = 0.0;   // imposed strain at which the open frame began       [-]
  std::uint64_t snapshots_passed = 0;  // snapshot strains behind the recorder (FrameRecorder)
  double wall_seconds = 0.0;      // wall time of the run's sessions before this one      [s]
  double loop_seconds = 0.0;      // of which in the step loop                            [s]
  std::int64_t movie_frames = 0;  // frames of the movie written (FrameRecorder)
};

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
