// /api/v1/sweeps: create (grid, points or adaptive), list and an adaptive sweep's plan (through
// the answer cache: ETag, If-None-Match), show with progress counts, cancel, export.
#include <map>
#include <sstream>

#include <spdlog/spdlog.h>

#include "exchange/export_format.hpp"
#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "http/page_limits.hpp"
#include "input/safe_text.hpp"
#include "plan/cost_model.hpp"
#include "routes/app.hpp"
#include "store/clock.hpp"
#include "views/csv_text.hpp"
#include "views/views.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// One line per job of the sweep: its parameters, state and result, and its point (the
// replicates read together: its id, label, share, runs and whether robust).
std::string export_csv(const json& rows, const json& points) {
  static const char* job_keys[] = {"id", "S", "R", "phi", "cells_per_unit", "eps_end", "state",
                                   "attempts", "last_error"};
  static const char* result_keys[] = {"status", "reason", "class", "confidence", "runner_up",
                                      "n_reflections", "band_speed_ratio", "eps_reached",
                                      "wall_seconds", "engine_version", "source_revision"};
  // A person's label beside the classifier's "class" (empty when nobody set one).
  static const char* human_keys[] = {"label", "reason", "by", "at"};
  static const char* point_keys[] = {"point_id", "label", "share", "runs", "robust"};
  std::map<std::int64_t, const json*> point_of;  // job id -> its point
  for (const json& p : points) {
    for (const json& job : p["jobs"]) point_of[job.get<std::int64_t>()] = &p;
  }
  std::ostringstream out;
  out << "job_id,S,R,phi,cells_per_unit,eps_end,state,attempts,last_error";
  for (const char* k : result_keys) out << ',' << k;
  for (const char* k : human_keys) out << ",human_" << k;
  out << ",point_id,point_label,point_share,point_runs,point_robust";
  out << ",scene\n";
  for (const json& row : rows) {
    bool first = true;
    for (const char* k : job_keys) {
      out << (first ? "" : ",") << csv_field(row[k]);
      first = false;
    }
    const json& r = row["result"];
    for (const char* k : result_keys) out << ',' << (r.is_null() ? "" : csv_field(r[k]));
    const json& h = row["human_label"];
    for (const char* k : human_keys) out << ',' << (h.is_null() ? "" : csv_field(h[k]));
    const auto p = point_of.find(row["id"].get<std::int64_t>());
    for (const char* k : point_keys) out << ',' << (p == point_of.end() ? "" : csv_field((*p->second)[k]));
    out << ',' << csv_field(row["scene"].dump()) << '\n';
  }
  return out.str();
}

}  // namespace

void register_sweep_routes(httplib::Server& server, App& app) {
  add_route(server, endpoints::create_sweep, [&app](const httplib::Request& req, httplib::Response& res) {
    const json body = parse_json_body(req);
    const SweepPlan plan = plan_sweep(body, app.limits);
    const CreatedSweep c =
        app.store.sweeps.create(sweep_rows(plan, app.store.config().engine_version), now_ms());
    // Points whose results other sweeps have are labelled already: plan past them.
    if (plan.adaptive) app.adaptive.advance(app.store, app.limits, c.id, now_ms());
    spdlog::info("sweep created id={} name=\"{}\" jobs={} new={} reused={} shared={} requeued={}",
                 c.id, log_escape(plan.name), c.n_jobs, c.n_new, c.n_reused, c.n_shared, c.n_requeued);
    const json out = views::created_sweep(*app.store.reads.sweep(c.id), c, plan.preset);
    res.set_header("Location", "/api/v1/sweeps/" + std::to_string(c.id));
    send_json(res, 201, out);
  });

  // The cost of a sweep before it is created: the planner's jobs (the same 422s as a create)
  // through the cost model; an adaptive sweep's budget at its initial grid's mean cost at its
  // finest level, or its budget in CPU-hours when lower.
  add_route(server, endpoints::estimate_sweep, [&app](const httplib::Request& req, httplib::Response& res) {
    const SweepPlan plan = plan_sweep(parse_json_body(req), app.limits);
    views::SweepEstimate e;
    e.jobs = plan.scenes.size();
    for (const SceneParams& p : plan.scenes) e.cpu_seconds += cost::cpu_seconds(p);
    e.max_jobs = plan.adaptive ? plan.adaptive->budget : e.jobs;
    e.max_cpu_seconds = e.jobs > 0 ? e.cpu_seconds * static_cast<double>(e.max_jobs) / e.jobs : 0;
    if (plan.adaptive) {
      // The budget in runs at the finest level's mean cost over the initial grid, or the budget
      // in CPU-hours when that is lower.
      double finest = 0;
      for (const SceneParams& p : plan.scenes) {
        finest += run_cpu_seconds(plan, {p.S, p.R}, static_cast<int>(plan.levels.size()) - 1);
      }
      e.max_cpu_seconds = std::min(plan.budget_cpu_seconds,
                                   finest * static_cast<double>(e.max_jobs) / static_cast<double>(e.jobs));
    }
    const std::int64_t now = now_ms();
    e.lease_seconds = app.options.lease_seconds;
    for (const auto& [name, at] : app.workers.list(now)) {
      if (now - at <= static_cast<std::int64_t>(app.options.lease_seconds * 1000)) ++e.workers;
    }
    send_json(res, 200, views::sweep_estimate(e));
  });

  add_route(server, endpoints::list_sweeps, [&app](const httplib::Request& req, httplib::Response& res) {
    const int limit = query_int(req, "limit", kDefaultPageRows, 1, kMaxPageRows);
    const int offset = query_int(req, "offset", 0, 0, kMaxOffset);
    app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
      return json_text(views::sweeps(app.store.reads.sweeps(limit, offset), limit, offset));
    });
  });

  add_route(server, endpoints::show_sweep,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const auto s = app.store.reads.sweep(path_id(req, 1, "sweep"));
               if (!s) throw ApiError(404, "id", "no such sweep");
               send_json(res, 200, views::sweep(*s));
             });

  add_route(server, endpoints::cancel_sweep,
              [&app](const httplib::Request& req, httplib::Response& res) {
                const std::int64_t id = path_id(req, 1, "sweep");
                // The body is empty or {}: a cancel takes no arguments.
                if (!req.body.empty()) {
                  const json body = parse_json_body(req);
                  if (!body.is_object()) throw ApiError(422, "body", "must be {} or empty");
                  for (const auto& [key, value] : body.items()) {
                    throw ApiError(422, valid_utf8(key.substr(0, 100)), "unknown key");
                  }
                }
                const auto cancelled = app.store.sweeps.cancel(id, now_ms());
                if (!cancelled) throw ApiError(404, "id", "no such sweep");
                spdlog::info("sweep cancelled id={} jobs_cancelled={}", id, *cancelled);
                send_json(res, 200, views::cancelled_sweep(id, *cancelled));
              });

  add_route(server, endpoints::sweep_plan,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const std::int64_t id = path_id(req, 1, "sweep");
               const int limit = query_int(req, "limit", 20, 0, 1000);
               // A plan is read from the database alone (the sweep's request and runs, under
               // limits fixed at start): the answer cache serves it, so that a page polling an
               // unchanged plan gets a 304 and the planner's ranking is not made again.
               app.answers.serve(req, res, app.store.db.writer.commits(), [&] {
                 const auto report = AdaptiveSweeps::report(app.store, app.limits, id);
                 if (!report) throw ApiError(404, "id", "no such sweep");
                 return json_text(views::sweep_plan(id, *report, static_cast<std::size_t>(limit)));
               });
             });

  add_route(server, endpoints::export_sweep,
             [&app](const httplib::Request& req, httplib::Response& res) {
               const std::int64_t id = path_id(req, 1, "sweep");
               const std::string format =
                   req.has_param("format") ? req.get_param_value("format") : "json";
               if (format != "json" && format != "csv" && format != "archive") {
                 throw ApiError(422, "format", "must be \"json\", \"csv\" or \"archive\"");
               }
               const std::string artifacts =
                   req.has_param("artifacts") ? req.get_param_value("artifacts") : "run_page";
               if (artifacts != "run_page" && artifacts != "none") {
                 throw ApiError(422, "artifacts", "must be \"run_page\" or \"none\"");
               }
               if (req.has_param("artifacts") && format != "archive") {
                 throw ApiError(422, "artifacts", "only with format=archive");
               }
               if (format == "archive") {  // the file another server imports (export_format.hpp)
                 const auto file =
                     export_sweep(app.store, id, req.get_header_value("Host"), now_ms(),
                                  artifacts == "none" ? ExportArtifacts::none
                                                      : ExportArtifacts::run_page);
                 if (!file) throw ApiError(404, "id", "no such sweep");
                 res.set_header("Content-Disposition",
                                "attachment; filename=\"sweep-" + std::to_string(id) + ".export.json\"");
                 // The file's size as saved: Content-Length is the compressed body's when the
                 // client accepts gzip, so the dashboard states this one before a download.
                 res.set_header("X-File-Size", std::to_string(file->size()));
                 res.status = 200;
                 res.set_content(*file, "application/json");
                 return;
               }
               const auto sweep = app.store.reads.sweep(id);
               const auto rows = app.store.reads.sweep_jobs(id);
               if (!sweep || !rows) throw ApiError(404, "id", "no such sweep");
               const std::string file = "sweep-" + std::to_string(id) + "." + format;
               res.set_header("Content-Disposition", "attachment; filename=\"" + file + "\"");
               const json points = json::parse(views::point_summaries(app.store.reads.sweep_map(id)));
               if (format == "csv") {
                 res.status = 200;
                 res.set_content(export_csv(views::sweep_jobs(*rows), points), "text/csv");
               } else {
                 send_json(res, 200, {{"sweep", views::sweep(*sweep)},
                                      {"jobs", views::sweep_jobs(*rows)},
                                      {"points", points}});
               }
             });
}

}  // namespace compaction::server
