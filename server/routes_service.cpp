// Service routes: health, metrics, the OpenAPI document, presets, the dashboard's static files,
// JSON answers for unknown API paths, and the request log.
#include <spdlog/spdlog.h>

#include "app.hpp"
#include "compaction/result.hpp"
#include "http_util.hpp"
#include "metrics.hpp"
#include "presets.hpp"

namespace compaction::server {

extern const char* const openapi_yaml;  // generated from server/openapi.yaml

using nlohmann::json;

void register_service_routes(httplib::Server& server, App& app) {
  server.Get("/api/v1/health", guarded([&app](const httplib::Request&, httplib::Response& res) {
    const StoreMetrics m = app.store.metrics();  // touches the database: a real check
    json jobs = json::object();
    for (const auto& [state, n] : m.jobs_by_state) jobs[state] = n;
    send_json(res, 200,
              {{"status", "ok"},
               {"engine_version", compaction::engine_version()},
               {"source_revision", compaction::source_revision()},
               {"jobs", jobs}});
  }));

  auto metrics = guarded([&app](const httplib::Request&, httplib::Response& res) {
    res.status = 200;
    res.set_content(render_metrics(app.store.metrics(), app.requests),
                    "text/plain; version=0.0.4");
  });
  server.Get("/metrics", metrics);
  server.Get("/api/v1/metrics", metrics);

  server.Get("/api/v1/openapi.yaml", [](const httplib::Request&, httplib::Response& res) {
    res.status = 200;
    res.set_content(openapi_yaml, "application/yaml");
  });

  server.Get("/api/v1/presets", [](const httplib::Request&, httplib::Response& res) {
    json out = json::array();
    for (const Preset& p : presets()) {
      out.push_back({{"name", p.name},
                     {"description", p.description},
                     {"cells_per_unit", p.cells_per_unit},
                     {"particles_per_cell", p.particles_per_cell},
                     {"cfl", p.cfl}});
    }
    send_json(res, 200, {{"presets", out}, {"default", default_preset_name}});
  });

  if (!app.options.web_dir.empty() && !server.set_mount_point("/", app.options.web_dir)) {
    spdlog::warn("static files: {} is not a directory; the dashboard is not served",
                 app.options.web_dir);
  }
}

void register_all_routes(httplib::Server& server, App& app) {
  register_sweep_routes(server, app);
  register_job_routes(server, app);
  register_queue_routes(server, app);
  register_service_routes(server, app);

  // Unknown paths and methods: a JSON error (the handlers' own errors already have a body).
  server.set_error_handler([](const httplib::Request& req, httplib::Response& res) {
    if (!res.body.empty()) return;
    const std::string message = res.status == 404   ? "no such resource: " + req.path
                                : res.status == 405 ? "method not allowed"
                                : res.status == 413 ? "request body too large"
                                                    : "request failed";
    send_json(res, res.status, ApiError(res.status, "path", message).body());
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
        spdlog::error("{} {}: {}", req.method, req.path, what);
        send_json(res, 500, ApiError(500, "", "internal error").body());
      });
  server.set_logger([&app](const httplib::Request& req, const httplib::Response& res) {
    if (res.status >= 500) {
      ++app.requests.server_error;
    } else if (res.status >= 400) {
      ++app.requests.client_error;
    } else {
      ++app.requests.ok;
    }
    if (res.status >= 400) {
      spdlog::info("http {} {} -> {} {}", req.method, req.path, res.status, res.body.substr(0, 300));
    } else {
      spdlog::debug("http {} {} -> {}", req.method, req.path, res.status);
    }
  });
}

}  // namespace compaction::server
