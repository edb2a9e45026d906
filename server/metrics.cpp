#include "metrics.hpp"

#include <map>
#include <sstream>

namespace compaction::server {

namespace {
std::int64_t lookup(const std::vector<std::pair<std::string, std::int64_t>>& v,
                    const std::string& key) {
  for (const auto& [k, n] : v) {
    if (k == key) return n;
  }
  return 0;
}
}  // namespace

std::string render_metrics(const StoreMetrics& m, const RequestCounters& requests) {
  std::ostringstream o;
  o << "# HELP compaction_jobs Jobs in the database by state.\n"
       "# TYPE compaction_jobs gauge\n";
  for (const char* s : {"queued", "running", "succeeded", "failed", "cancelled"}) {
    o << "compaction_jobs{state=\"" << s << "\"} " << lookup(m.jobs_by_state, s) << "\n";
  }
  o << "# HELP compaction_queue_depth Jobs waiting for a worker.\n"
       "# TYPE compaction_queue_depth gauge\n"
       "compaction_queue_depth "
    << lookup(m.jobs_by_state, "queued") << "\n";
  o << "# HELP compaction_jobs_done_total Results stored, by run status.\n"
       "# TYPE compaction_jobs_done_total counter\n";
  for (const char* s : {"ok", "unstable"}) {
    o << "compaction_jobs_done_total{status=\"" << s << "\"} " << lookup(m.results_by_status, s)
      << "\n";
  }
  o << "# HELP compaction_lease_expiries_total Leases that expired without a heartbeat.\n"
       "# TYPE compaction_lease_expiries_total counter\n"
       "compaction_lease_expiries_total "
    << lookup(m.events_by_kind, "lease_expired") << "\n";
  o << "# HELP compaction_job_events_total Job events by kind.\n"
       "# TYPE compaction_job_events_total counter\n";
  for (const char* k : {"queued", "leased", "released", "lease_expired", "failed", "retry",
                        "succeeded", "cancelled"}) {
    o << "compaction_job_events_total{kind=\"" << k << "\"} " << lookup(m.events_by_kind, k)
      << "\n";
  }
  o << "# HELP compaction_sweeps_total Sweeps created.\n"
       "# TYPE compaction_sweeps_total counter\n"
       "compaction_sweeps_total "
    << m.sweeps << "\n";
  o << "# HELP compaction_http_requests_total HTTP requests answered since the server started.\n"
       "# TYPE compaction_http_requests_total counter\n"
       "compaction_http_requests_total{class=\"2xx\"} "
    << requests.ok.load() << "\n"
    << "compaction_http_requests_total{class=\"4xx\"} " << requests.client_error.load() << "\n"
    << "compaction_http_requests_total{class=\"5xx\"} " << requests.server_error.load() << "\n";
  return o.str();
}

}  // namespace compaction::server
