#include "views/checkpoint_views.hpp"

namespace compaction::server::views {

using nlohmann::json;

json checkpoint(const StoredCheckpoint& c) {
  return {{"job_id", c.job_id},
          {"url", "/api/v1/jobs/" + std::to_string(c.job_id) + "/checkpoint"},
          {"size", c.size},
          {"step", c.step},
          {"eps", c.eps},
          {"worker", c.worker},
          {"attempt", c.attempt},
          {"created_at", c.created_at}};
}

json resumes(const std::vector<Resume>& list) {
  json out = json::array();
  for (const Resume& r : list) {
    out.push_back({{"at", r.at},
                   {"worker", r.worker},
                   {"attempt", r.attempt},
                   {"step", r.step},
                   {"eps", r.eps}});
  }
  return out;
}

}  // namespace compaction::server::views
