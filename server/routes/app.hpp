// What the HTTP routes share: the store, the options, request counters, the answers clients
// poll, the workers seen, the planning of adaptive sweeps.
#pragma once

#include <atomic>
#include <cstdint>

#include <httplib.h>

#include "config/options.hpp"
#include "http/answer_cache.hpp"
#include "plan/adaptive_sweeps.hpp"
#include "plan/planner.hpp"
#include "routes/workers_seen.hpp"
#include "store/store.hpp"

namespace compaction::server {

struct RequestCounters {
  std::atomic<std::int64_t> ok{0};            // 2xx
  std::atomic<std::int64_t> client_error{0};  // 4xx
  std::atomic<std::int64_t> server_error{0};  // 5xx
};

struct App {
  Store& store;
  ServerOptions options;
  PlannerLimits limits;
  RequestCounters requests;
  AnswerCache answers;
  WorkersSeen workers;
  AdaptiveSweeps adaptive;
};

// One registration function per resource (routes_*.cpp).
void register_sweep_routes(httplib::Server& server, App& app);
void register_job_routes(httplib::Server& server, App& app);
void register_queue_routes(httplib::Server& server, App& app);
void register_service_routes(httplib::Server& server, App& app);
void register_label_routes(httplib::Server& server, App& app);
void register_import_routes(httplib::Server& server, App& app);

// Everything above plus error handling and logging: the whole API on one server.
class HttpServer;
void register_all_routes(HttpServer& server, App& app);

}  // namespace compaction::server
