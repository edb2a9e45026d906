// A job's checkpoint as its row in job_checkpoints (migration 0007) says, read inside the
// caller's transaction: checkpoint_store.hpp reads it for its own calls, the queue in the
// transaction of a lease (the lease answer names it) and of a completion (the file goes).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "store/sqlite.hpp"
#include "store/store_db.hpp"

namespace compaction::server {

struct StoredCheckpoint {
  std::int64_t job_id = 0;
  std::string path;        // relative to the checkpoints folder
  std::int64_t size = 0;   // [bytes]
  std::int64_t step = 0;   // time steps the run had taken
  double eps = 0.0;        // imposed strain it had reached
  std::string worker;      // that uploaded it
  int attempt = 0;         // of the lease that uploaded it
  Millis created_at = 0;
};

std::optional<StoredCheckpoint> find_checkpoint(sqlite::Database& db, std::int64_t job_id);

}  // namespace compaction::server
