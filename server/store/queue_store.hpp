// The job queue: leases with tokens and deadlines, heartbeats, completion with the result and
// its artifacts, failure with retries, release, and the rescue of expired leases. Every change
// is one guarded UPDATE in a write transaction (`WHERE id = ? AND state = 'running' AND
// lease_token = ?`), so zero rows changed means the lease was lost (job_states.hpp lists who
// moves a job where). "Now" is a parameter of every call, so tests control the clock.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/artifact.hpp"
#include "store/checkpoint_rows.hpp"
#include "store/job_states.hpp"
#include "store/store_db.hpp"

namespace compaction::server {

struct Lease {
  std::int64_t job_id = 0;
  std::string token;
  Millis deadline = 0;
  std::string scene;   // canonical scene JSON
  int attempt = 0;
  int max_attempts = 0;
  std::optional<StoredCheckpoint> checkpoint;  // an earlier lease's: the run goes on from it
};

struct ResultRecord {
  std::string status;  // "ok" or "unstable"
  std::string reason;
  std::string scene;   // the parameters the run used (canonical JSON)
  std::string engine_version;
  std::string source_revision;
  std::optional<std::string> cls, runner_up;
  std::optional<double> confidence, band_speed_ratio, eps_reached, wall_seconds;
  std::optional<std::int64_t> n_reflections;
  std::optional<std::string> features;  // JSON
  std::string summary;                  // summary.json as uploaded
  std::vector<Artifact> artifacts;
};

// Where an imported result was computed (import_store.hpp); none for a result computed here.
struct ResultOrigin {
  std::string database;  // the computing database's id
  std::int64_t job = 0;  // the job's id there
  Millis imported_at = 0;
};

// Inserts a result and its artifact rows (the files already written, at `paths` in the order of
// r.artifacts) inside the caller's write transaction. The primary key on results.job_id refuses
// a second result: a result is never overwritten.
void insert_result(sqlite::Database& writer, std::int64_t job_id, const ResultRecord& r,
                   const std::string& worker, Millis created_at,
                   const std::vector<std::string>& paths,
                   const std::optional<ResultOrigin>& origin = std::nullopt);

enum class LeaseCheck {
  ok,
  unknown_job,  // no such job
  lost,         // the token is not the live lease of a running job (stale, expired, cancelled)
};

struct FailOutcome {
  LeaseCheck check = LeaseCheck::ok;
  JobState state = JobState::failed;  // queued again (retry) or failed
  Millis run_after = 0;
};

class QueueStore {
 public:
  explicit QueueStore(StoreDb& db) : db_(db) {}

  // Takes the best queued job (priority, then age) of this engine version.
  std::optional<Lease> lease(const std::string& worker, const std::string& engine_version,
                             Millis now);
  // worker, when given, receives the name of the worker that holds the lease.
  LeaseCheck heartbeat(std::int64_t job_id, const std::string& token, double eps, Millis now,
                       Millis& deadline, std::string* worker = nullptr);
  // Who asks for a lease: the worker's name and the engine version it runs.
  struct LeaseRequest {
    std::string worker;
    std::string engine_version;
  };
  // What a completion's transaction found for the caller's follow-ups (none of which needs a
  // read of its own then).
  struct FollowUps {
    std::optional<Lease> next;                  // the worker's next job, when it asked for one
    bool checkpoint = false;                    // the job has a checkpoint, which may go now
    std::vector<std::int64_t> adaptive_sweeps;  // the live adaptive sweeps that hold the job
  };
  // Writes the artifact files (outside the write lock), then the result and its artifact rows
  // in one transaction, shared with the completions that arrive at the same time (the store's
  // group_commit; a lost lease changes nothing and leaves the others' rows alone). With `next`,
  // the same transaction also leases the worker's next job
  // (as lease() would; none when the queue has nothing for it): one commit and one round trip
  // where a worker that goes on would need two.
  LeaseCheck complete(std::int64_t job_id, const std::string& token, const ResultRecord& r,
                      Millis now, const std::optional<LeaseRequest>& next = std::nullopt,
                      FollowUps* follow_ups = nullptr);
  FailOutcome fail(std::int64_t job_id, const std::string& token, const std::string& reason,
                   bool retryable, Millis now);
  // The worker gives the job back (it is stopping): queued at once, the attempt not counted.
  LeaseCheck release(std::int64_t job_id, const std::string& token, Millis now);
  // Whether token is the live lease of the job now (a cheap check before reading an upload;
  // complete() checks again inside its transaction).
  LeaseCheck check_lease(std::int64_t job_id, const std::string& token);
  // The lease rescuer: running jobs whose deadline passed go back to the queue (or to failed
  // when their attempts are used up), each counted under its worker in worker_lease_expiries.
  // Returns the number of jobs moved.
  int requeue_expired(Millis now);
  // The canonical scene and engine version of a job (to check an upload against them).
  std::optional<std::pair<std::string, std::string>> job_scene(std::int64_t job_id);
  // Both in one read: whether token is the job's live lease, and if so its scene and engine
  // version (an upload's checks before complete(), which checks the lease again).
  struct LeasedJob {
    LeaseCheck check = LeaseCheck::ok;
    std::string scene, engine_version;
  };
  LeasedJob leased_job(std::int64_t job_id, const std::string& token);

 private:
  Millis backoff(int attempts) const;
  // The claim of lease(), inside the caller's write transaction.
  std::optional<Lease> claim(const std::string& worker, const std::string& engine_version,
                             Millis now);

  StoreDb& db_;
};

}  // namespace compaction::server
