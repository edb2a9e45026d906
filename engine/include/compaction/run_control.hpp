// What the caller of a run controls besides the scene: progress callbacks, cancellation, the
// movie's file, checkpoints and resumes (compaction/simulation.hpp runs it).
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <string>

#include "compaction/checkpoint.hpp"

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
  // When set and true, the run stops before its next step with status "cancelled" (after
  // writing a checkpoint when checkpoint_file is set).
  const std::atomic<bool>* cancel = nullptr;

  // When set and the scene's movie_d_eps > 0: the file the movie is written to as the run goes
  // (compaction/movie.hpp; the runner's is <out>/movie.bin).
  std::string movie_file;

  // Checkpoints (checkpoint.hpp). When checkpoint_file is set, the run writes its full state
  // there (a temporary file renamed over it) whenever checkpoint_every seconds of wall time
  // have passed since the last one (<= 0: never by time), and once more when cancelled.
  std::string checkpoint_file;
  double checkpoint_every = 0.0;  // [s] of wall time
  // Called after each checkpoint written, from the thread that runs the scene.
  std::function<void(const CheckpointInfo&)> on_checkpoint;
  // When set, the run goes on from this checkpoint instead of starting at t = 0; a checkpoint
  // of another engine version or scene (threads aside) throws CheckpointRefused.
  std::string resume_file;
  // Called once the checkpoint of resume_file is loaded, before the first step.
  std::function<void(const CheckpointInfo&)> on_resume;
};

}  // namespace compaction
