// The worker's side of the queue: lease a job, heartbeat, complete (upload the result), fail,
// release. The worker token is checked by the request guard before a body is read; every call
// after the lease needs the live lease token (a stale one answers 409 and changes nothing).
#include <cmath>

#include <spdlog/spdlog.h>

#include "app.hpp"
#include "checkpoint_routes.hpp"
#include "clock.hpp"
#include "endpoints.hpp"
#include "http_util.hpp"
#include "result_intake.hpp"
#include "safe_text.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

void check_lease(LeaseCheck c) {
  if (c == LeaseCheck::unknown_job) throw ApiError(404, "id", "no such job");
  if (c == LeaseCheck::lost) {
    throw ApiError(409, "lease_token",
                   "the lease is not live (expired, released, cancelled or never held)");
  }
}

std::string lease_token(const json& body) { return body_string(body, "lease_token", 200); }

void lease(App& app, const httplib::Request& req, httplib::Response& res) {
  const json body = parse_json_body(req);
  const std::string worker = body_string(body, "worker", 200);
  const std::string version = body_string(body, "engine_version", 100);
  for (const auto& [key, value] : body.items()) {
    if (key != "worker" && key != "engine_version") throw ApiError(422, key, "unknown key");
  }
  const Millis now = now_ms();
  app.workers.seen(worker, now);
  const auto lease = app.store.queue.lease(worker, version, now);
  if (!lease) {
    res.status = 204;  // nothing to do now
    return;
  }
  spdlog::info("job leased id={} worker={} attempt={}/{}", lease->job_id, log_escape(worker),
               lease->attempt, lease->max_attempts);
  send_json(res, 200,
            {{"job_id", lease->job_id},
             {"lease_token", lease->token},
             {"lease_deadline", lease->deadline},
             {"lease_seconds", app.options.lease_seconds},
             {"attempt", lease->attempt},
             {"max_attempts", lease->max_attempts},
             {"scene", json::parse(lease->scene)},
             // the run's checkpoint when an earlier lease uploaded one: go on from it
             {"checkpoint", checkpoint_of(app, lease->job_id)}});
}

void heartbeat(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  const json body = parse_json_body(req);
  const std::string token = lease_token(body);
  double eps = 0.0;
  if (body.contains("eps")) {
    const json& e = body["eps"];
    if (!e.is_number() || !std::isfinite(e.get<double>()) || e.get<double>() < 0.0 ||
        e.get<double>() > 1.0) {
      throw ApiError(422, "eps", "must be a number in [0, 1], got " + describe(e));
    }
    eps = e.get<double>();
  }
  const std::optional<ResumeReport> resumed = parse_resume_report(body);
  Millis deadline = 0;
  std::string worker;
  const Millis now = now_ms();
  check_lease(app.store.queue.heartbeat(id, token, eps, now, deadline, &worker));
  app.workers.seen(worker, now);
  if (resumed) {
    check_lease(app.store.checkpoints.record_resume(id, token, resumed->step, resumed->eps, now));
    spdlog::info("job resumed id={} worker={} step={} eps={:.6g}", id, log_escape(worker),
                 resumed->step, resumed->eps);
  }
  send_json(res, 200, {{"lease_deadline", deadline}});
}

void complete(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  if (!req.has_file("lease_token")) throw ApiError(422, "lease_token", "is required");
  if (!req.has_file("summary")) throw ApiError(422, "summary", "is required");
  const std::string token = req.get_file_value("lease_token").content;
  check_lease(app.store.queue.check_lease(id, token));
  const auto job = app.store.queue.job_scene(id);
  if (!job) throw ApiError(404, "id", "no such job");
  std::vector<UploadedFile> files;
  for (const auto& [name, part] : req.files) {
    if (name == "lease_token" || name == "summary") continue;
    if (name != "files") {
      throw ApiError(422, "form[" + valid_utf8(name.substr(0, 100)) + "]",
                     "unknown form field (expected lease_token, summary, files)");
    }
    files.push_back({part.filename, part.content});
  }
  ResultRecord r = intake_result(req.get_file_value("summary").content, job->first,
                                 job->second, std::move(files));
  check_lease(app.store.queue.complete(id, token, r, now_ms()));
  spdlog::info("job succeeded id={} status={} class={} artifacts={}", id, r.status,
               r.cls.value_or("-"), r.artifacts.size());
  app.store.checkpoints.remove_if_done(id);
  app.adaptive.job_ended(app.store, app.limits, id, now_ms());
  send_json(res, 200, {{"job_id", id}, {"state", "succeeded"}, {"status", r.status}});
}

void fail(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  const json body = parse_json_body(req);
  const std::string token = lease_token(body);
  const std::string reason = body_string(body, "reason", 20000, TextKind::free_text);
  bool retryable = true;
  if (body.contains("retryable")) {
    if (!body["retryable"].is_boolean()) throw ApiError(422, "retryable", "must be true or false");
    retryable = body["retryable"].get<bool>();
  }
  const FailOutcome out = app.store.queue.fail(id, token, reason, retryable, now_ms());
  check_lease(out.check);
  spdlog::warn("job failed id={} retryable={} now={} reason=\"{}\"", id, retryable,
               to_string(out.state), log_escape(reason, 500));
  if (out.state == JobState::failed) {
    app.store.checkpoints.remove_if_done(id);
    app.adaptive.job_ended(app.store, app.limits, id, now_ms());
  }
  send_json(res, 200, {{"job_id", id}, {"state", to_string(out.state)}, {"run_after", out.run_after}});
}

void release(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  const json body = parse_json_body(req);
  check_lease(app.store.queue.release(id, lease_token(body), now_ms()));
  spdlog::info("job released id={}", id);
  send_json(res, 200, {{"job_id", id}, {"state", "queued"}});
}

}  // namespace

void register_queue_routes(httplib::Server& server, App& app) {
  using namespace std::placeholders;
  add_route(server, endpoints::lease, std::bind(lease, std::ref(app), _1, _2));
  add_route(server, endpoints::heartbeat, std::bind(heartbeat, std::ref(app), _1, _2));
  add_route(server, endpoints::complete, std::bind(complete, std::ref(app), _1, _2));
  add_route(server, endpoints::fail, std::bind(fail, std::ref(app), _1, _2));
  add_route(server, endpoints::release, std::bind(release, std::ref(app), _1, _2));
}

}  // namespace compaction::server
