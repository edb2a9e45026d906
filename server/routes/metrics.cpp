#include "routes/metrics.hpp"

#include <cstdio>
#include <map>
#include <sstream>

#include "input/safe_text.hpp"

namespace compaction::server {

namespace {
std::int64_t lookup(const std::vector<std::pair<std::string, std::int64_t>>& v,
                    const std::string& key) {
  for (const auto& [k, n] : v) {
    if (k == key) return n;
  }
  return 0;
}
std::string seconds(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f", s);
  return buf;
}

}  // namespace

std::string label_value(const std::string& v) {
  std::string out;
  for (char c : valid_utf8(v)) {
    if (c == '\\') {
      out += "\\\\";
    } else if (c == '"') {
      out += "\\\"";
    } else if (c == '\n') {
      out += "\\n";
    } else {
      out += c;
    }
  }
  return out;
}

std::string render_metrics(const ScrapeMetrics& scrape, const RequestCounters& requests,
                           const std::vector<std::pair<std::string, std::int64_t>>& workers_seen,
                           const BuildInfo& build, const GroupCommit::Totals& writes) {
  const StoreMetrics& m = scrape.store;
  std::ostringstream o;
  o << "# HELP compaction_build_info The server's build: engine version and source revision.\n"
       "# TYPE compaction_build_info gauge\n"
       "compaction_build_info{version=\""
    << label_value(build.version) << "\",revision=\"" << label_value(build.source_revision)
    << "\"} 1\n";
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
                        "succeeded", "cancelled", "checkpoint", "resumed"}) {
    o << "compaction_job_events_total{kind=\"" << k << "\"} " << lookup(m.events_by_kind, k)
      << "\n";
  }
  o << "# HELP compaction_job_duration_seconds Succeeded jobs by the time from the lease that "
       "succeeded to its result.\n"
       "# TYPE compaction_job_duration_seconds histogram\n";
  for (std::size_t i = 0; i < scrape.duration_buckets.size(); ++i) {
    o << "compaction_job_duration_seconds_bucket{le=\"" << job_duration_buckets_seconds[i]
      << "\"} " << scrape.duration_buckets[i] << "\n";
  }
  o << "compaction_job_duration_seconds_bucket{le=\"+Inf\"} " << scrape.duration_count << "\n"
    << "compaction_job_duration_seconds_sum " << seconds(scrape.duration_sum_seconds) << "\n"
    << "compaction_job_duration_seconds_count " << scrape.duration_count << "\n";
  o << "# HELP compaction_worker_last_seen_timestamp_seconds When a worker last asked for a "
       "lease or sent a heartbeat (workers seen in the last 24 h, at most 500).\n"
       "# TYPE compaction_worker_last_seen_timestamp_seconds gauge\n";
  for (const auto& [worker, at] : workers_seen) {
    o << "compaction_worker_last_seen_timestamp_seconds{worker=\"" << label_value(worker)
      << "\"} " << seconds(static_cast<double>(at) / 1000.0) << "\n";
  }
  o << "# HELP compaction_worker_lease_expiries_total Leases that expired, by the worker that "
       "held them (the 100 workers with the newest expiries).\n"
       "# TYPE compaction_worker_lease_expiries_total counter\n";
  for (const auto& [worker, n] : scrape.lease_expiries_by_worker) {
    o << "compaction_worker_lease_expiries_total{worker=\"" << label_value(worker) << "\"} " << n
      << "\n";
  }
  o << "# HELP compaction_sweeps_total Sweeps created.\n"
       "# TYPE compaction_sweeps_total counter\n"
       "compaction_sweeps_total "
    << m.sweeps << "\n";
  o << "# HELP compaction_completion_transactions_total Write transactions that stored results "
       "since the server started (completions arriving together share one).\n"
       "# TYPE compaction_completion_transactions_total counter\n"
       "compaction_completion_transactions_total "
    << writes.batches << "\n";
  o << "# HELP compaction_completion_transaction_items_total Completions those transactions "
       "held (divided by the transactions: completions per commit).\n"
       "# TYPE compaction_completion_transaction_items_total counter\n"
       "compaction_completion_transaction_items_total "
    << writes.items << "\n";
  o << "# HELP compaction_http_requests_total HTTP requests answered since the server started.\n"
       "# TYPE compaction_http_requests_total counter\n"
       "compaction_http_requests_total{class=\"2xx\"} "
    << requests.ok.load() << "\n"
    << "compaction_http_requests_total{class=\"4xx\"} " << requests.client_error.load() << "\n"
    << "compaction_http_requests_total{class=\"5xx\"} " << requests.server_error.load() << "\n";
  return o.str();
}

}  // namespace compaction::server
