// Runs one leased job: writes its scene, starts compaction-run as a child process
// (docs/runner.md), turns its progress lines into heartbeats, and reports the end:
//   exit 0            -> upload summary.json and the bundle's files (status ok or unstable)
//   exit 2            -> fail, not retryable (invalid input)
//   exit 3, or killed
//   by SIGTERM/SIGINT -> stopped from outside (a batch system ends every process of a job, the
//                        runner too): release the lease, the attempt is not counted
//   exit 1, other,
//   other signals     -> fail, retryable, with the reason and the tail of the runner's stderr
//   heartbeat 409     -> the lease is lost (expired or cancelled): stop the run, report nothing
//   stop requested    -> stop the run, release the lease (the job requeues at once)
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "api_client.hpp"
#include "child_process.hpp"
#include "options.hpp"

namespace compaction::worker {

struct LeasedJob {
  std::int64_t id = 0;
  std::string token;
  nlohmann::json scene;
  double lease_seconds = 60;
  int attempt = 1;
  int max_attempts = 1;
};

enum class JobEnd {
  succeeded,       // result stored (ok or unstable)
  failed,          // reported as failed (the server retries or gives up)
  lease_lost,      // someone else owns the job now; nothing was reported
  released,        // the worker is stopping or the run was stopped from outside; the job
                   // went back to the queue
  not_reported,    // the server could not be reached in time; the lease will expire
};
const char* to_string(JobEnd e);

class JobRunner {
 public:
  JobRunner(const WorkerOptions& options, ApiClient& client, const std::atomic<bool>& stop);
  JobEnd run(const LeasedJob& job);

 private:
  // How a run went: stopped by the worker (end), or ended by itself (exit, and its "done" line).
  struct Watched {
    std::optional<JobEnd> end;
    ExitStatus exit;
    std::string done_status, done_reason;
  };
  // Follows the runner's progress lines with heartbeats until it exits, the lease is lost or
  // the worker stops.
  Watched watch(const LeasedJob& job, ChildProcess& child);
  // What the runner's exit means: an upload, or a failure with its reason.
  JobEnd conclude(const LeasedJob& job, const Watched& w, const std::string& out_dir,
                  const std::string& stderr_file);
  JobEnd report_failure(const LeasedJob& job, const std::string& reason, bool retryable);
  JobEnd upload(const LeasedJob& job, const std::string& out_dir);
  JobEnd release(const LeasedJob& job);

  const WorkerOptions& options_;
  ApiClient& client_;
  const std::atomic<bool>& stop_;
};

}  // namespace compaction::worker
