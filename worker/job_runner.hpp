// Runs one leased job: writes its scene, starts compaction-run as a child process
// (docs/runner.md), turns its progress lines into heartbeats, and reports the end:
//   exit 0            -> upload summary.json and the bundle's files (status ok or unstable)
//   exit 2            -> fail, not retryable (invalid input)
//   exit 3, or killed
//   by SIGTERM/SIGINT -> stopped from outside (a batch system ends every process of a job, the
//                        runner too): upload the run's latest checkpoint, release the lease,
//                        the attempt is not counted
//   exit 4            -> the checkpoint the lease came with was refused: run again from t = 0
//   exit 1, other,
//   other signals     -> fail, retryable, with the reason and the tail of the runner's stderr
//   heartbeat 409     -> the lease is lost (expired or cancelled): stop the run, report nothing
//   stop requested    -> stop the run (it writes a final checkpoint), upload the checkpoint,
//                        release the lease (the job requeues at once)
// Checkpoints (docs/service.md, "Checkpoints"): the runner writes one every --checkpoint-every
// seconds and when it is stopped; the worker uploads each one under its lease. A lease that
// comes with a checkpoint is run with --resume from it, and the first heartbeat after the
// runner confirms reports the resume. A lost lease uploads nothing (the token is dead).
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
  nlohmann::json checkpoint;  // the lease answer's "checkpoint" (null: none), see checkpoint_of
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
  // next: the worker goes on after this job, so the upload of its result asks for the next
  // one (ApiClient::complete); none when it stops after it.
  JobEnd run(const LeasedJob& job, const std::optional<NextLease>& next = std::nullopt);

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
                  const std::string& stderr_file, const std::optional<NextLease>& next);
  JobEnd report_failure(const LeasedJob& job, const std::string& reason, bool retryable);
  JobEnd upload(const LeasedJob& job, const std::string& out_dir,
                const std::optional<NextLease>& next);
  JobEnd release(const LeasedJob& job);
  // One line of the runner's stdout: progress, checkpoints (each uploaded), the resume, done.
  void handle_line(const LeasedJob& job, const std::string& line, double& eps, Watched& w);
  // Downloads the lease's checkpoint into the job's folder; empty when there is none or it
  // cannot be had (the run then starts at t = 0).
  std::string fetch_checkpoint(const LeasedJob& job, const std::string& dir);
  // Uploads the runner's newest checkpoint unless it is uploaded already.
  void upload_checkpoint(const LeasedJob& job);

  // The run's newest checkpoint the runner reported (step < 0: none yet).
  struct Checkpointed {
    std::string file;
    std::int64_t step = -1;
    double eps = 0.0;
    bool uploaded = false;
  };
  Checkpointed checkpoint_;
  nlohmann::json resume_report_;  // {"step", "eps"} for the next heartbeat, null once sent

  const WorkerOptions& options_;
  ApiClient& client_;
  const std::atomic<bool>& stop_;
};

}  // namespace compaction::worker
