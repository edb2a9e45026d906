// Command-line options of compaction-worker.
#pragma once

#include <optional>
#include <string>

#include "compaction/checkpoint.hpp"

namespace compaction::worker {

struct WorkerOptions {
  std::string server = "http://127.0.0.1:8080";  // base URL of compaction-server
  std::string token;             // worker token (env COMPACTION_WORKER_TOKEN)
  int threads = 1;               // threads of each run (the scene's "threads")
  int max_jobs = 0;              // exit after this many jobs (0: no limit)
  double idle_exit = 0;          // exit after this long without a job (0: never)     [s]
  std::string runner;            // compaction-run (default: next to this executable)
  std::string work_dir;          // scratch folder for the runs' bundles
  std::string name;              // worker name in leases (default host:pid)
  double poll_interval = 2;      // wait between lease attempts on an empty queue     [s]
  bool keep_work = false;        // keep each job's folder after it ends
  // wall time between the runner's checkpoints, each uploaded (0: only when stopped)   [s]
  double checkpoint_every = compaction::kDefaultCheckpointEvery;
  std::string log_level = "info";
};

// Parses argv with the programs' common grammar (engine/cli/command_line.hpp); nullopt after
// --help or --version (exit_code 0) or an error naming the flag and its value (exit_code 2).
// The runner must be an executable file (its version is asked for later: runner_version.hpp).
std::optional<WorkerOptions> parse_worker_options(int argc, const char* const* argv,
                                                  int& exit_code);

// The text of --help, with the defaults and ranges of the flags.
std::string worker_usage();

}  // namespace compaction::worker
