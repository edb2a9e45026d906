// Command-line arguments of compaction-run.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction::cli {

enum class ProgressMode { automatic, bar, log, json, none };

struct Options {
  SceneParams params;
  std::string out_dir;
  ProgressMode progress = ProgressMode::automatic;
  bool help = false;
  bool version = false;
};

// Parses argv. On failure returns the problems, one "flag: message" each (nothing run).
std::vector<std::string> parse(int argc, const char* const* argv, Options& out);

std::string help_text();

}  // namespace compaction::cli
