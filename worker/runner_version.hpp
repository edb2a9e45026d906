// The engine a runner was built from, as `compaction-run --version` says it:
// "compaction-run VERSION (REVISION)". The worker asks once at start and leases jobs for that
// engine version, so that a --runner of another build gets jobs it can run (the server refuses
// a result whose engine version is not the job's).
#pragma once

#include <optional>
#include <string>

namespace compaction::worker {

struct RunnerVersion {
  std::string engine_version;
  std::string source_revision;
};

// Reads the first line of `compaction-run --version`; nullopt when it is not of that form.
std::optional<RunnerVersion> parse_runner_version(const std::string& line);

// Runs `runner --version` and reads its answer, waiting at most timeout_seconds. Throws
// std::runtime_error saying why when the runner cannot say (does not start, fails, times out,
// answers something else).
RunnerVersion ask_runner_version(const std::string& runner, double timeout_seconds = 10);

}  // namespace compaction::worker
