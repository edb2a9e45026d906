// The checkpoint endpoints (POST and GET /api/v1/jobs/{id}/checkpoint) and what the queue's
// routes and the job detail take from checkpoints: the lease answer's "checkpoint", the
// heartbeat's "resumed" report, the detail's "checkpoint" and "resumes".
#pragma once

#include <cstdint>
#include <optional>

#include <httplib.h>
#include <nlohmann/json.hpp>

#include "routes/app.hpp"

namespace compaction::server {

void register_checkpoint_routes(httplib::Server& server, App& app);

// A heartbeat's "resumed": {"step": integer >= 0, "eps": number in [0, 1]} (absent: nullopt);
// throws ApiError 422 naming resumed.step or resumed.eps.
struct ResumeReport {
  std::int64_t step = 0;
  double eps = 0.0;
};
std::optional<ResumeReport> parse_resume_report(const nlohmann::json& heartbeat_body);

// The job's stored checkpoint as the job detail shows it, or null (a lease answer shows the
// checkpoint its lease read, views::checkpoint).
nlohmann::json checkpoint_of(App& app, std::int64_t job_id);

// Adds "checkpoint" and "resumes" to a job's detail.
void add_checkpoint_detail(App& app, std::int64_t job_id, nlohmann::json& detail);

}  // namespace compaction::server
