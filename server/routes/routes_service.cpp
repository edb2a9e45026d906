// Service routes: health, metrics, the OpenAPI document, presets, the dashboard's static files,
// JSON answers for unknown API paths, and the request log.
#include <functional>
#include <string>

#include <spdlog/spdlog.h>

#include "compaction/presets.hpp"
#include "compaction/result.hpp"
#include "http/answer_cache.hpp"
#include "http/endpoints.hpp"
#include "http/http_server.hpp"
#include "http/http_util.hpp"
#include "http/page_limits.hpp"
#include "http/request_guard.hpp"
#include "input/safe_text.hpp"
#include "routes/app.hpp"
#include "routes/checkpoint_routes.hpp"
#include "routes/metrics.hpp"
#include "routes/run_query.hpp"
#include "plan/adaptive_plan.hpp"
#include "store/clock.hpp"

namespace compaction::server {

extern const char* const openapi_yaml;  // generated from server/openapi.yaml

using nlohmann::json;

namespace {

json range_json(const compaction::Range& r) { return {{"lo", r.lo}, {"hi", r.hi}, {"open", r.open}}; }

// The movie's interval: its range when set, 0 for none, and the scene's default.
json movie_json() {
  json j = range_json(compaction::limits::movie_d_eps);
  j["none"] = 0;
  j["default"] = compaction::SceneParams{}.movie_d_eps;
  return j;
}

// What GET /jobs (the run table) takes: its columns, those it sorts by, its parameters, the
// most rows of its CSV and the length of its text search.
json jobs_limits_json() {
  json columns = json::array(), sort = json::array();
  for (const RunColumn& c : run_columns()) {
    columns.push_back(c.name);
    if (c.sortable) sort.push_back(c.name);
  }
  return {{"columns", columns},
          {"sort", sort},
          {"parameters", jobs_parameters()},
          {"max_csv_rows", kMaxCsvRows},
          {"q_max_bytes", kMaxSearchBytes}};
}

// What a sweep request may hold: the planner's rules and the scene's ranges, from their homes.
json limits_json(const PlannerLimits& l) {
  namespace lim = compaction::limits;
  return {{"sweep",
           {{"max_points", l.max_points},
            {"name_max_bytes", kMaxNameBytes},
            {"priority", {{"lo", kPriorityMin}, {"hi", kPriorityMax}, {"default", kDefaultPriority}}},
            {"max_attempts", {{"lo", 1}, {"hi", l.max_attempts}, {"default", kDefaultMaxAttempts}}},
            {"max_upload_bytes", l.max_bundle_bytes},
            {"max_seeds", kMaxSeeds}}},
          // replicates: {n, perturbation}, n in [1, max_n], the perturbation in the scene's range
          {"replicates", {{"max_n", kMaxSeeds}, {"perturbation", range_json(lim::perturbation)}}},
          {"scene",
           {{"S", range_json(lim::S)},
            {"R", range_json(lim::R)},
            {"phi", range_json(lim::phi)},
            {"cells_per_strut", range_json(lim::cells_per_strut)},
            {"cells_per_unit", range_json(lim::cells_per_unit)},
            {"eps_end", range_json(lim::eps_end)},
            {"snapshot_eps", range_json(lim::snapshot_eps)},
            {"max_snapshots", compaction::kMaxSnapshots},
            {"movie_d_eps", movie_json()}}},
          // Where the paper's classification holds (the scene's phi is what the engine runs).
          {"model", {{"phi", {{"lo", compaction::kModelPhiMin}, {"hi", compaction::kModelPhiMax}}}}},
          {"adaptive",
           {{"initial", {{"S", adaptive::kDefaultInitialPerAxis}, {"R", adaptive::kDefaultInitialPerAxis}}},
            {"min_initial", adaptive::kMinInitialPerAxis},
            {"resolution_decades", adaptive::kDefaultResolutionDecades},
            {"finest_resolution_decades", adaptive::kFinestResolutionDecades},
            {"budget", std::min<long long>(adaptive::kDefaultBudget, static_cast<long long>(l.max_points))},
            {"in_flight", adaptive::kDefaultInFlight},
            {"max_levels", adaptive::kMaxLevels}}},
          {"lists", {{"default_limit", kDefaultPageRows}, {"max_limit", kMaxPageRows}, {"max_offset", kMaxOffset}}},
          {"jobs", jobs_limits_json()}};
}

// Counts an answer by its class and logs it (a refusal with its body, at info).
void log_request(App& app, const std::string& method, const std::string& path, int status,
                 const std::string& body) {
  if (status >= 500) {
    ++app.requests.server_error;
  } else if (status >= 400) {
    ++app.requests.client_error;
  } else {
    ++app.requests.ok;
  }
  if (status >= 400) {
    spdlog::info("http {} {} -> {} {}", log_escape(method, 20), log_escape(path), status,
                 log_escape(body, 300));
  } else {
    spdlog::debug("http {} {} -> {}", log_escape(method, 20), log_escape(path), status);
  }
}

}  // namespace

void register_service_routes(httplib::Server& server, App& app) {
  add_route(server, endpoints::health, [&app](const httplib::Request&, httplib::Response& res) {
    const StoreMetrics m = app.store.reads.metrics();  // touches the database: a real check
    json jobs = json::object();
    for (const auto& [state, n] : m.jobs_by_state) jobs[state] = n;
    send_json(res, 200,
              {{"status", "ok"},
               {"engine_version", compaction::engine_version()},
               {"source_revision", compaction::source_revision()},
               {"jobs", jobs},
               // Whether a role's writes need a token, so a page asks for one only where needed.
               {"tokens", {{"submit", app.options.tokens.open(TokenKind::submit) ? "open" : "required"},
                           {"worker", app.options.tokens.open(TokenKind::worker) ? "open" : "required"}}}});
  });

  auto metrics = [&app](const httplib::Request&, httplib::Response& res) {
    res.status = 200;
    res.set_content(render_metrics(app.store.reads.scrape_metrics(), app.requests,
                                   app.workers.list(now_ms()),
                                   {app.store.config().engine_version, compaction::source_revision()},
                                   app.store.db.group_commit.totals()),
                    "text/plain; version=0.0.4");
  };
  add_route(server, endpoints::metrics, metrics);
  add_route(server, endpoints::api_metrics, metrics);

  add_route(server, endpoints::openapi, [](const httplib::Request&, httplib::Response& res) {
    res.status = 200;
    res.set_content(openapi_yaml, "application/yaml");
  });

  add_route(server, endpoints::presets, [](const httplib::Request&, httplib::Response& res) {
    json out = json::array();
    for (const compaction::Preset& p : compaction::presets()) {
      json preset = compaction::preset_json(p);
      preset["name"] = p.name;
      preset["description"] = p.description;
      out.push_back(preset);
    }
    send_json(res, 200, {{"presets", out}, {"default", compaction::kDefaultPreset}});
  });

  add_route(server, endpoints::limits, [&app](const httplib::Request&, httplib::Response& res) {
    send_json(res, 200, limits_json(app.limits));
  });

  if (!app.options.web_dir.empty() && !server.set_mount_point("/", app.options.web_dir)) {
    spdlog::warn("static files: {} is not a directory; the dashboard is not served",
                 app.options.web_dir);
  }
  // The dashboard's files carry a tag of their content and are revalidated at each use
  // (no-cache): a visit after the first costs a 304 a file, and an upgraded file is never
  // served stale.
  server.set_file_request_handler([](const httplib::Request& req, httplib::Response& res) {
    const std::string tag = fmt::format("\"{:016x}-{:x}\"", std::hash<std::string>{}(res.body),
                                        res.body.size());
    res.set_header("ETag", tag);
    res.set_header("Cache-Control", "no-cache");
    if (if_none_match_names(req.get_header_value("If-None-Match"), tag)) {
      res.status = 304;
      res.body.clear();
    }
  });
}

void register_all_routes(HttpServer& server, App& app) {
  install_request_guard(server, guard_config(app.options));
  // Artifacts and errors are data: a browser must never guess another type for them.
  server.set_default_headers({{"X-Content-Type-Options", "nosniff"}});
  register_sweep_routes(server, app);
  register_job_routes(server, app);
  register_queue_routes(server, app);
  register_checkpoint_routes(server, app);
  register_service_routes(server, app);
  register_label_routes(server, app);
  register_import_routes(server, app);

  // Unknown paths and methods: a JSON error (the handlers' own errors already have a body).
  // Errors cpp-httplib found itself (before or instead of a handler): the field is the part
  // of the request at fault.
  server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    // What the library could not parse leaves the connection at an unknown place in the
    // stream (an unread body, half a header): the answer is the last on it.
    if (res.status == 400 || res.status == 413 || res.status == 414) {
      HttpServer::close_after_response();
    }
    try {
      std::string field = "path", message;
      switch (res.status) {
        case 404: message = "no such resource: " + valid_utf8(req.path.substr(0, 200)); break;
        case 405: message = "method not allowed"; break;
        case 413: field = "body", message = "request body too large"; break;
        case 414: message = "request line too long"; break;
        case 416: field = "Range", message = "invalid Range header"; break;
        case 400:
          field = "request";
          message = "malformed request: bad request line or headers, or a truncated or "
                    "malformed body";
          // The library's multipart parser (cpp-httplib 0.11) also refuses a body whose close
          // delimiter ends it without the CRLF that curl, browsers and compaction-worker send.
          if (req.is_multipart_form_data()) {
            field = "body";
            message = "malformed multipart/form-data body: truncated, or its close delimiter "
                      "(--boundary--) not followed by CRLF";
          }
          break;
        default: field = "request", message = "request failed"; break;
      }
      send_json(res, res.status, ApiError(res.status, field, message).body());
    } catch (...) {
      res.set_content(R"({"error": {"field": "request", "message": "request failed"}})",
                      "application/json");
    }
  });
  server.set_exception_handler(
      [](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
        std::string what = "unknown";
        try {
          std::rethrow_exception(ep);
        } catch (const std::exception& e) {
          what = e.what();
        } catch (...) {
        }
        send_internal_error(req, res, what);
      });
  server.set_logger([&app](const httplib::Request& req, const httplib::Response& res) {
    log_request(app, req.method, req.path, res.status, res.body);
  });
  server.set_refusal_logger(
      [&app](const std::string& method, const std::string& path, const ApiError& e) {
        log_request(app, method.empty() ? "-" : method, path.empty() ? "-" : path, e.status,
                    json_text(e.body()));
      });
}

}  // namespace compaction::server
