// Reads of the store as typed records (views.hpp shapes them for the REST API): sweeps with
// their counts by state, jobs with their results, a job's events, the phase map's points,
// artifacts, metrics. Each call is one read transaction on a read-only connection of its own.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "store/job_states.hpp"
#include "store/label_store.hpp"
#include "store/queue_store.hpp"
#include "store/run_table.hpp"
#include "store/store_db.hpp"

namespace compaction::server {

struct StateCounts {
  std::int64_t queued = 0, running = 0, succeeded = 0, failed = 0, cancelled = 0;
  std::int64_t total() const { return queued + running + succeeded + failed + cancelled; }
  std::int64_t open() const { return queued + running; }
};

struct SweepRecord {
  std::int64_t id = 0;
  std::string name;
  std::string request;  // JSON text
  std::int64_t priority = 0;
  Millis created_at = 0;
  std::optional<Millis> cancelled_at;
  StateCounts counts;
  // An imported sweep: the database and sweep it was computed as, and the import's provenance
  // (JSON text); none for a sweep made here.
  std::optional<std::string> origin_database, origin;
  std::optional<std::int64_t> origin_sweep;
};

struct StoredResult {
  std::string status, reason, engine_version, source_revision, worker;
  std::optional<std::string> cls, runner_up, features;  // features: JSON text
  std::optional<double> confidence, band_speed_ratio, eps_reached, wall_seconds;
  std::optional<std::int64_t> n_reflections;
  Millis created_at = 0;
  // An imported result: the database and job that computed it, and when it came; none when it
  // was computed here.
  std::optional<std::string> origin_database;
  std::optional<std::int64_t> origin_job;
  std::optional<Millis> imported_at;
};

struct JobRecord {
  std::int64_t id = 0;
  std::string state;
  double S = 0, R = 0, phi = 0, eps_end = 0;
  std::int64_t cells_per_unit = 0;
  std::string engine_version;
  std::string scene;  // JSON text
  std::int64_t priority = 0, attempts = 0, max_attempts = 0;
  std::optional<std::string> worker, last_error;
  std::optional<double> progress_eps;
  Millis created_at = 0, run_after = 0;
  std::optional<Millis> started_at, heartbeat_at, finished_at, lease_deadline;
  std::optional<StoredResult> result;
  std::optional<HumanLabel> human_label;  // a person's label beside the classifier's
  std::int64_t point_id = 0;  // the point the run is a replicate of (migration 0011)
};

struct EventRecord {
  Millis at = 0;
  std::string kind;
  std::int64_t attempt = 0;
  std::optional<std::string> worker;
  std::string message;
};

inline constexpr std::size_t kMaxListedReplicates = 1000;

struct JobDetail {
  JobRecord job;
  std::vector<std::int64_t> sweeps;
  // The other runs of its point (its replicates: migration 0011), the first kMaxListedReplicates.
  std::vector<std::int64_t> replicates;
  std::vector<EventRecord> events;  // the newest max_events_per_job
  std::int64_t events_dropped = 0;
  std::optional<std::string> summary;  // summary.json of the result
};

struct PhaseMapPoint {
  double S = 0, R = 0, phi = 0, eps_end = 0;
  std::string state;
  std::optional<std::string> cls, runner_up, status;
  std::optional<double> confidence, band_speed_ratio, progress_eps;
  // c_b/V's standard error and the transit reading with its uncertainty, from the features
  std::optional<double> band_speed_error, band_speed_transit, band_speed_transit_error;
  // the band's early stage in the velocity map: its middle and its leading edge, with their
  // standard errors
  std::optional<double> band_speed_early, band_speed_early_error, band_speed_lead,
      band_speed_lead_error;
  std::optional<std::int64_t> n_reflections;
  std::int64_t job_id = 0, cells_per_unit = 0;
  std::int64_t point_id = 0;  // the point the run is a replicate of (migration 0011)
  std::optional<std::string> human_label;  // a person's label; `cls` stays the classifier's
  std::string structure = "regular";  // the scene's voids; scenes older than the key: regular
  std::string geometry = "pseudo1d";  // the scene's column (migration 0013)
};

struct ArtifactInfo {
  std::string name, content_type;
  std::int64_t size = 0;
};

template <typename T>
struct Page {
  std::vector<T> items;
  std::int64_t total = 0;
};

struct StoreMetrics {
  std::vector<std::pair<std::string, std::int64_t>> jobs_by_state;
  std::vector<std::pair<std::string, std::int64_t>> events_by_kind;  // every event ever logged
  std::vector<std::pair<std::string, std::int64_t>> results_by_status;
  std::int64_t sweeps = 0;
};

// The upper bounds (seconds) of the job-duration histogram's buckets: a run takes from seconds
// (the fast preset) to hours (the reference resolution).
inline constexpr double job_duration_buckets_seconds[] = {1,    10,    60,    300,   900,
                                                          3600, 10800, 43200, 86400};
// Workers whose lease expiries the metrics list: those with the newest expiries.
constexpr int max_workers_with_expiries = 100;

// What /metrics adds to StoreMetrics, read in the same transaction.
struct ScrapeMetrics {
  StoreMetrics store;
  // Succeeded jobs by the time from the lease that succeeded to its result: cumulative counts
  // per bucket of job_duration_buckets_seconds, then the count and the sum (seconds) of all.
  std::vector<std::int64_t> duration_buckets;
  std::int64_t duration_count = 0;
  double duration_sum_seconds = 0;
  // Lease expiries by worker (the newest max_workers_with_expiries), by name.
  std::vector<std::pair<std::string, std::int64_t>> lease_expiries_by_worker;
};

class StoreReads {
 public:
  explicit StoreReads(StoreDb& db) : db_(db) {}

  std::optional<SweepRecord> sweep(std::int64_t id);
  Page<SweepRecord> sweeps(int limit, int offset);
  // Every job of the sweep with its result, in request order; nullopt: unknown sweep.
  std::optional<std::vector<JobRecord>> sweep_jobs(std::int64_t id);
  // The adaptive sweeps (a request with "adaptive") not cancelled: all of them, or those that
  // hold the job. In id order.
  std::vector<std::int64_t> live_adaptive_sweeps();
  std::vector<std::int64_t> live_adaptive_sweeps_of_job(std::int64_t job_id);
  // The run table's page (run_table.hpp) as the jobs' full records, in one read transaction.
  RunPage<JobRecord> jobs(const RunQuery& q);
  std::optional<JobDetail> job(std::int64_t id);
  // The runs at phi (within 1e-9) of one geometry (to_string(Geometry): the scene's), of one
  // sweep and one grid (cells per unit cell) when given.
  std::vector<PhaseMapPoint> phase_map(double phi, std::optional<std::int64_t> sweep_id,
                                       std::optional<std::int64_t> cells_per_unit = std::nullopt,
                                       const std::string& geometry = "pseudo1d");
  // The map's reading of every job of a sweep, in the sweep's order (its export's points).
  std::vector<PhaseMapPoint> sweep_map(std::int64_t sweep_id);
  std::optional<std::vector<ArtifactInfo>> artifacts(std::int64_t job_id);
  std::optional<Artifact> artifact(std::int64_t job_id, const std::string& name);
  StoreMetrics metrics();
  ScrapeMetrics scrape_metrics();
  // A fingerprint of every table's content (tests: "nothing changed in the database").
  std::string fingerprint();

 private:
  StoreDb& db_;
};

}  // namespace compaction::server
