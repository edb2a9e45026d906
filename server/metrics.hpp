// Prometheus text exposition of the queue (jobs by state, queue depth, results, lease
// expiries and other job events) and of the HTTP requests served.
#pragma once

#include <string>

#include "app.hpp"

namespace compaction::server {

std::string render_metrics(const StoreMetrics& m, const RequestCounters& requests);

}  // namespace compaction::server
