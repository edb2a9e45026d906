// Checkpoints: the full state of a run between two time steps in one file
// (schema/checkpoint-format.md), so that a run stopped by a batch system's time limit or a
// preemption goes on from where it stood and ends with the bits an uninterrupted run gives.
// run_scene writes them (RunControl::checkpoint_file) and resumes from one
// (RunControl::resume_file).
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "compaction/params.hpp"

namespace compaction {

// Wall time between two checkpoints of a run when nothing else is asked (compaction-run
// --checkpoint-every, compaction-worker --checkpoint-every), and the range both accept
// (0: only when the run is stopped). Writing the default scene's checkpoint takes tens of
// milliseconds (docs/runner.md), so the overhead at this interval is far below 0.1 %; what it
// bounds is the work lost when a run dies without its final checkpoint (kill -9, a lost node).
inline constexpr double kDefaultCheckpointEvery = 600.0;  // [s]
inline constexpr Range kCheckpointEveryRange{0.0, 1e7};   // [s]

// What a checkpoint file says of itself (its header).
struct CheckpointInfo {
  std::string engine_version;   // of the engine that wrote it; only the same version resumes
  std::string source_revision;  // of the build that wrote it (informative)
  std::int64_t step = 0;        // time steps taken
  double t = 0.0;               // simulated time                                     [s]
  double eps = 0.0;             // imposed strain V t / h0                             [-]
  std::int64_t frames = 0;      // frames recorded
  int threads = 1;              // threads of the run that wrote it (same count: same bits)
  std::uint64_t bytes = 0;      // size of the file
  double write_seconds = 0.0;   // wall time the write took (0 when read back)
};

// A checkpoint that cannot be resumed: not a checkpoint, damaged (checksum), of another format
// or engine version, or of another scene. what() says which, with the values that differ.
class CheckpointRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Reads and checks a checkpoint's header (magic, format version, checksum); throws
// CheckpointRefused. Does not check the engine version or the scene (run_scene does).
CheckpointInfo read_checkpoint_info(const std::string& path);

}  // namespace compaction
