// The states of a job and who moves a job into and out of each. The schema enforces the set
// (schema/migrations/0001_init.sql: CHECK on jobs.state); every transition is one guarded UPDATE
// in queue_store.cpp or sweep_store.cpp (`WHERE id = ? AND state = ...`), so zero rows changed means the move lost.
#pragma once

#include <optional>
#include <string_view>

namespace compaction::server {

enum class JobState {
  // In:  SweepStore::create (new parameters, or a failed/cancelled job a new sweep wants),
  //      QueueStore::fail (a retryable failure with attempts left, after a backoff: run_after),
  //      QueueStore::release (the worker stopped; requeued at once, the attempt not counted),
  //      QueueStore::requeue_expired (the lease rescuer: the deadline passed without heartbeat).
  // Out: QueueStore::lease -> running; SweepStore::cancel -> cancelled.
  queued,
  // In:  QueueStore::lease (a worker holds a lease token and a deadline).
  // Out: QueueStore::complete -> succeeded; QueueStore::fail -> queued or failed;
  //      QueueStore::release -> queued; QueueStore::requeue_expired -> queued or failed;
  //      SweepStore::cancel -> cancelled (the worker learns it at its next heartbeat: 409).
  running,
  // In:  QueueStore::complete with the live lease token (the result row is written in the same
  //      transaction, status "ok" or "unstable"). Out: never; the result is reused by later sweeps.
  succeeded,
  // In:  QueueStore::fail (not retryable, or attempts exhausted), QueueStore::requeue_expired
  //      (attempts exhausted). Out: SweepStore::create -> queued with fresh attempts.
  failed,
  // In:  SweepStore::cancel (no other live sweep wants the job).
  // Out: SweepStore::create -> queued with fresh attempts.
  cancelled,
};

constexpr std::string_view to_string(JobState s) {
  switch (s) {
    case JobState::queued: return "queued";
    case JobState::running: return "running";
    case JobState::succeeded: return "succeeded";
    case JobState::failed: return "failed";
    case JobState::cancelled: return "cancelled";
  }
  return "unknown";
}

constexpr std::optional<JobState> parse_job_state(std::string_view s) {
  for (JobState j : {JobState::queued, JobState::running, JobState::succeeded, JobState::failed,
                     JobState::cancelled}) {
    if (to_string(j) == s) return j;
  }
  return std::nullopt;
}

}  // namespace compaction::server
