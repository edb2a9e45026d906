// The REST documents of checkpoints and resumes (checkpoint_store.hpp): the "checkpoint" of a
// lease answer and of GET /jobs/{id}, and the job's "resumes".
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "store/checkpoint_store.hpp"

namespace compaction::server::views {

// {job_id, url, size, step, eps, worker, attempt, created_at}; url: where a worker downloads it.
nlohmann::json checkpoint(const StoredCheckpoint& c);
// [{at, worker, attempt, step, eps}], oldest first.
nlohmann::json resumes(const std::vector<Resume>& list);

}  // namespace compaction::server::views
