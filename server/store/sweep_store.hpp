// Sweeps as the store writes them: a new sweep with its jobs (identical computations shared,
// finished ones reused, failed or cancelled ones queued again), the cancel of a sweep, and the
// live adaptive sweeps that hold a job. The store takes rows; the planner (planner.hpp:
// sweep_rows) turns a request into them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "store/store_db.hpp"

namespace compaction::server {

// One distinct computation of a sweep.
struct NewJob {
  std::string identity;  // engine version + canonical scene: equal identities are computed once
  std::string scene;     // canonical scene JSON
  double S = 0, R = 0, phi = 0, eps_end = 0;
  int cells_per_unit = 0;
  std::string structure;  // the scene's voids: "regular" or "random"
};

struct NewSweep {
  std::string name;
  std::string request;  // the accepted request body (JSON text)
  int priority = 0;
  int max_attempts = 3;
  std::vector<NewJob> jobs;  // distinct, in request order
};

struct CreatedSweep {
  std::int64_t id = 0;
  std::int64_t n_jobs = 0;     // distinct scenes of the sweep
  std::int64_t n_new = 0;      // jobs created for it
  std::int64_t n_reused = 0;   // already succeeded: the stored result is reused
  std::int64_t n_shared = 0;   // already queued or running for another sweep
  std::int64_t n_requeued = 0; // failed or cancelled before, queued again
};

// The adaptive sweeps not cancelled that hold the job, in id order, read inside the caller's
// transaction (StoreReads reads it on its own; the queue within a completion's).
std::vector<std::int64_t> live_adaptive_sweeps_of_job(sqlite::Database& db, std::int64_t job_id);

class SweepStore {
 public:
  explicit SweepStore(StoreDb& db) : db_(db) {}

  CreatedSweep create(const NewSweep& sweep, Millis now);
  // Adds jobs to a sweep after those it has (an adaptive sweep's further points), each as
  // create() does: new, reused, shared or queued again, with the priority and attempts given.
  // nullopt for an unknown sweep.
  std::optional<CreatedSweep> add_jobs(std::int64_t sweep_id, const std::vector<NewJob>& jobs,
                                       int priority, int max_attempts, Millis now);
  // Cancels the sweep's queued and running jobs that no other live sweep contains; returns
  // how many, or nullopt for an unknown sweep. Cancelling twice is harmless.
  std::optional<std::int64_t> cancel(std::int64_t id, Millis now);

 private:
  // Inserts or finds each job and links it to the sweep from `position` on; in the caller's
  // transaction, under the writer lock.
  void link_jobs(std::int64_t sweep_id, std::int64_t position, const std::vector<NewJob>& jobs,
                 int priority, int max_attempts, Millis now, CreatedSweep& out);

  StoreDb& db_;
};

}  // namespace compaction::server
