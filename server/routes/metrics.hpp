// Prometheus text exposition of the queue (jobs by state, queue depth, results, lease
// expiries and other job events, job durations, completions per shared transaction), of the workers (last seen, lease expiries by
// worker), of the HTTP requests served and of the build.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "routes/app.hpp"
#include "store/group_commit.hpp"

namespace compaction::server {

struct BuildInfo {
  std::string version;          // the engine version the server queues jobs for
  std::string source_revision;  // the commit the server was built from
};

// workers_seen: name and time (ms since the epoch) of the last call, as WorkersSeen::list;
// writes: the group commit's transactions since the server started.
std::string render_metrics(const ScrapeMetrics& m, const RequestCounters& requests,
                           const std::vector<std::pair<std::string, std::int64_t>>& workers_seen,
                           const BuildInfo& build, const GroupCommit::Totals& writes);

// A label value in the text format: backslash, double quote and newline escaped.
std::string label_value(const std::string& v);

}  // namespace compaction::server
