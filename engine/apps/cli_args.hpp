// Command-line arguments of compaction-run (command_line.hpp gives the grammar).
#pragma once

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction::cli {

enum class ProgressMode { automatic, bar, log, json, none };

struct Options {
  SceneParams params;
  // The numerics preset the scene starts from (--preset; else the one its numerics match,
  // else "default") and the preset's keys the scene sets otherwise (for summary.json).
  std::string preset;
  nlohmann::json overridden;
  std::string out_dir;
  ProgressMode progress = ProgressMode::automatic;
  // Checkpoints (docs/runner.md): where to write them, how often (wall seconds; 0: only when
  // stopped by SIGTERM/SIGINT), and the checkpoint to resume from (empty: start at t = 0).
  std::string checkpoint_file;
  double checkpoint_every = 0.0;
  std::string resume_file;
  bool check = false;  // --check: validate the scene, print it with its grid, run nothing
};


// Parses argv into `out`. std::nullopt: run; otherwise the exit code (0 after --help or
// --version, 2 after invalid input, each problem reported on stderr as
// "compaction-run: --flag (field): message").
std::optional<int> parse(int argc, const char* const* argv, Options& out);

}  // namespace compaction::cli
