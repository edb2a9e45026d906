// The states of a job and who moves a job into and out of each. The schema enforces the set
// (schema/migrations/0001_init.sql: CHECK on jobs.state); every transition is one guarded UPDATE
// in job_store.cpp (`WHERE id = ? AND state = ...`), so zero rows changed means the move lost.
#pragma once

#include <optional>
#include <string_view>

namespace compaction::server {

enum class JobState {
  // In:  JobStore::create_sweep (new parameters, or a failed/cancelled job a new sweep wants),
  //      JobStore::fail (a retryable failure with attempts left, after a backoff: run_after),
  //      JobStore::release (the worker stopped; requeued at once, the attempt not counted),
  //      JobStore::requeue_expired (the lease rescuer: the deadline passed without heartbeat).
  // Out: JobStore::lease -> running; JobStore::cancel_sweep -> cancelled.
  queued,
  // In:  JobStore::lease (a worker holds a lease token and a deadline).
  // Out: JobStore::complete -> succeeded; JobStore::fail -> queued or failed;
  //      JobStore::release -> queued; JobStore::requeue_expired -> queued or failed;
  //      JobStore::cancel_sweep -> cancelled (the worker learns it at its next heartbeat: 409).
  running,
  // In:  JobStore::complete with the live lease token (the result row is written in the same
  //      transaction, status "ok" or "unstable"). Out: never; the result is reused by later sweeps.
  succeeded,
  // In:  JobStore::fail (not retryable, or attempts exhausted), JobStore::requeue_expired
  //      (attempts exhausted). Out: JobStore::create_sweep -> queued with fresh attempts.
  failed,
  // In:  JobStore::cancel_sweep (no other live sweep wants the job).
  // Out: JobStore::create_sweep -> queued with fresh attempts.
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

constexpr bool is_terminal(JobState s) {
  return s == JobState::succeeded || s == JobState::failed || s == JobState::cancelled;
}

}  // namespace compaction::server
