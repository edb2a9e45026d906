// The job store: sweeps, the job queue with leases, results and artifacts in SQLite.
// The only code that holds SQL queries (with sqlite.cpp, the connection, and migrations.cpp,
// the schema files). Every write is one BEGIN IMMEDIATE transaction of prepared statements;
// every state change is a guarded UPDATE (job_states.hpp lists who moves a job where).
// "Now" is a parameter of every call that depends on time, so tests control the clock.
// Reads return JSON documents shaped as the REST API answers them; each read uses a read-only
// connection of its own (WAL), so no read waits for a write or for another read, and the
// writer's lock is never held while artifact files are written (artifact_files.hpp).
#pragma once

#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "artifact_files.hpp"
#include "job_states.hpp"
#include "planner.hpp"
#include "sqlite.hpp"

namespace compaction::server {

using Millis = std::int64_t;  // milliseconds since the Unix epoch

// The event log keeps this many of the newest events per job (older ones are counted in the
// job's events_dropped); a job that is leased and given back forever cannot grow it.
constexpr int max_events_per_job = 50;

struct StoreConfig {
  Millis lease_ms = 60'000;          // a lease lasts this long after a lease or heartbeat
  Millis backoff_base_ms = 5'000;    // retry n waits base * 2^(n-1), capped at backoff_max_ms
  Millis backoff_max_ms = 600'000;
  std::string engine_version;        // the version the identity of new jobs carries
};

struct CreatedSweep {
  std::int64_t id = 0;
  std::int64_t n_jobs = 0;     // distinct scenes of the sweep
  std::int64_t n_new = 0;      // jobs created for it
  std::int64_t n_reused = 0;   // already succeeded: the stored result is reused
  std::int64_t n_shared = 0;   // already queued or running for another sweep
  std::int64_t n_requeued = 0; // failed or cancelled before, queued again
};

struct JobFilter {
  std::optional<std::int64_t> sweep_id;
  std::optional<JobState> state;
  std::optional<double> phi;
  int limit = 100;
  int offset = 0;
};

struct Lease {
  std::int64_t job_id = 0;
  std::string token;
  Millis deadline = 0;
  std::string scene;   // canonical scene JSON
  int attempt = 0;
  int max_attempts = 0;
};

// What a worker's upload becomes (checked by result_intake before it gets here).
struct Artifact {
  std::string name;
  std::string content_type;
  std::string data;
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

struct StoreMetrics {
  std::vector<std::pair<std::string, std::int64_t>> jobs_by_state;
  std::vector<std::pair<std::string, std::int64_t>> events_by_kind;  // leased, lease_expired ...
  std::vector<std::pair<std::string, std::int64_t>> results_by_status;
  std::int64_t sweeps = 0;
};

class JobStore {
 public:
  // Opens the database and applies the pending migrations.
  JobStore(const std::string& path, StoreConfig config);

  const StoreConfig& config() const { return config_; }

  // Sweeps.
  CreatedSweep create_sweep(const SweepPlan& plan, Millis now);
  std::optional<nlohmann::json> sweep(std::int64_t id);
  nlohmann::json list_sweeps(int limit, int offset);
  // Cancels the sweep's queued and running jobs that no other live sweep contains.
  // nullopt: unknown sweep. Cancelling twice is harmless.
  std::optional<nlohmann::json> cancel_sweep(std::int64_t id, Millis now);
  // One row per job of the sweep: parameters, state and result (for the export).
  std::optional<nlohmann::json> sweep_results(std::int64_t id);

  // Jobs.
  nlohmann::json list_jobs(const JobFilter& filter);
  std::optional<nlohmann::json> job(std::int64_t id);
  nlohmann::json phase_map(double phi, std::optional<std::int64_t> sweep_id);

  // The queue. lease() takes the best queued job (priority, then age) of this engine version.
  std::optional<Lease> lease(const std::string& worker, const std::string& engine_version,
                             Millis now);
  LeaseCheck heartbeat(std::int64_t job_id, const std::string& token, double eps, Millis now,
                       Millis& deadline);
  LeaseCheck complete(std::int64_t job_id, const std::string& token, const ResultRecord& r,
                      Millis now);
  FailOutcome fail(std::int64_t job_id, const std::string& token, const std::string& reason,
                   bool retryable, Millis now);
  // The worker gives the job back (it is stopping): queued at once, the attempt not counted.
  LeaseCheck release(std::int64_t job_id, const std::string& token, Millis now);
  // Whether token is the live lease of the job now (a cheap check before reading an upload;
  // complete() checks again inside its transaction).
  LeaseCheck check_lease(std::int64_t job_id, const std::string& token);
  // The lease rescuer: running jobs whose deadline passed go back to the queue (or to failed
  // when their attempts are used up). Returns the number of jobs moved.
  int requeue_expired(Millis now);
  // The canonical scene and engine version of a job (to check an upload against them).
  std::optional<std::pair<std::string, std::string>> job_scene(std::int64_t job_id);

  // Artifacts of a job's result.
  std::optional<nlohmann::json> list_artifacts(std::int64_t job_id);
  std::optional<Artifact> artifact(std::int64_t job_id, const std::string& name);

  StoreMetrics metrics();
  // A fingerprint of every table's content (tests: "nothing changed in the database").
  std::string fingerprint();

 private:
  Millis backoff(int attempts) const;
  void log_event(std::int64_t job_id, Millis at, const char* kind, int attempt,
                 const std::optional<std::string>& worker, const std::string& message);
  nlohmann::json job_row_json(sqlite::Statement& s);
  static nlohmann::json counts_for_sweep(sqlite::Database& db, std::int64_t id);

  StoreConfig config_;
  std::mutex mutex_;          // the writer connection, used by one thread at a time
  sqlite::Database db_;       // every write, in BEGIN IMMEDIATE transactions
  sqlite::ReaderPool readers_;  // every read, each in a read transaction of its own connection
  ArtifactFiles files_;       // the bytes of results' artifacts
};

}  // namespace compaction::server
