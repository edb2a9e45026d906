// Checkpoints of runs (docs/service.md, "Checkpoints"): the newest checkpoint of each job, as a
// file below <db>.checkpoints/ and a row in job_checkpoints (migration 0007), and the resumes
// from them (job_resumes). A worker that stops mid-run uploads its checkpoint under its live
// lease before it releases the lease; the next lease of the job is handed it; the worker that
// goes on from it reports the resume with its first heartbeat. The checkpoint is removed when
// the job succeeds or fails for good; a cancelled job keeps it (a later sweep may want it again).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "store/artifact_files.hpp"
#include "store/checkpoint_rows.hpp"
#include "store/queue_store.hpp"
#include "store/store_db.hpp"

namespace compaction::server {

struct Resume {
  Millis at = 0;
  std::string worker;      // that went on
  int attempt = 0;         // of its lease
  std::int64_t step = 0;   // of the checkpoint it went on from
  double eps = 0.0;
};

class CheckpointStore {
 public:
  // root: the checkpoints folder (created). Removes the checkpoints of jobs that are done and
  // the folders no row names (an upload that crashed before its commit).
  CheckpointStore(StoreDb& db, std::filesystem::path root);

  // Stores the checkpoint of the live lease `token` (the file first, then the row, in place of
  // an earlier one, and a 'checkpoint' event). Throws std::runtime_error on I/O errors.
  LeaseCheck put(std::int64_t job_id, const std::string& token, const std::string& bytes,
                 std::int64_t step, double eps, Millis now);
  std::optional<StoredCheckpoint> find(std::int64_t job_id);
  // The bytes of a stored checkpoint; throws std::runtime_error when its file is missing.
  std::string read(const StoredCheckpoint& c) const;

  // The worker of the live lease went on from the job's checkpoint at step and eps: a row in
  // job_resumes and a 'resumed' event.
  LeaseCheck record_resume(std::int64_t job_id, const std::string& token, std::int64_t step,
                           double eps, Millis now);
  std::vector<Resume> resumes(std::int64_t job_id);

  // Removes the job's checkpoint when the job is succeeded or failed (after its last move).
  void remove_if_done(std::int64_t job_id);

 private:
  StoreDb& db_;
  ArtifactFiles files_;
};

}  // namespace compaction::server
