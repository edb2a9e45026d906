// The worker's side of the queue: lease a job, heartbeat, complete (upload the result), fail,
// release. The worker token is checked by the request guard before a body is read; every call
// after the lease needs the live lease token (a stale one answers 409 and changes nothing).
#include <cmath>

#include <spdlog/spdlog.h>

#include "exchange/result_intake.hpp"
#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"
#include "routes/app.hpp"
#include "routes/checkpoint_routes.hpp"
#include "store/clock.hpp"
#include "views/checkpoint_views.hpp"

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

// A lease request's body: {"worker", "engine_version"}, nothing else.
QueueStore::LeaseRequest lease_request(const json& body) {
  QueueStore::LeaseRequest r{body_string(body, "worker", 200),
                             body_string(body, "engine_version", 100)};
  for (const auto& [key, value] : body.items()) {
    if (key != "worker" && key != "engine_version") throw ApiError(422, key, "unknown key");
  }
  return r;
}

// What a worker is told of its lease.
json lease_answer(App& app, const Lease& lease, const std::string& worker) {
  spdlog::info("job leased id={} worker={} attempt={}/{}", lease.job_id, log_escape(worker),
               lease.attempt, lease.max_attempts);
  return {{"job_id", lease.job_id},
          {"lease_token", lease.token},
          {"lease_deadline", lease.deadline},
          {"lease_seconds", app.options.lease_seconds},
          {"attempt", lease.attempt},
          {"max_attempts", lease.max_attempts},
          {"scene", json::parse(lease.scene)},
          // the run's checkpoint when an earlier lease uploaded one: go on from it
          {"checkpoint", lease.checkpoint ? views::checkpoint(*lease.checkpoint) : json(nullptr)}};
}

void lease(App& app, const httplib::Request& req, httplib::Response& res) {
  const QueueStore::LeaseRequest who = lease_request(parse_json_body(req));
  const Millis now = now_ms();
  app.workers.seen(who.worker, now);
  const auto lease = app.store.queue.lease(who.worker, who.engine_version, now);
  if (!lease) {
    res.status = 204;  // nothing to do now
    return;
  }
  send_json(res, 200, lease_answer(app, *lease, who.worker));
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
  // A worker that goes on asks for its next job with the result (the lease body as a field).
  std::optional<QueueStore::LeaseRequest> next;
  if (req.has_file("next_lease")) {
    try {
      next = lease_request(parse_client_json(req.get_file_value("next_lease").content,
                                             "next_lease", 422));
    } catch (ApiError& e) {
      e.field = e.field == "next_lease" ? e.field : "next_lease." + e.field;
      throw;
    }
  }
  const QueueStore::LeasedJob job = app.store.queue.leased_job(id, token);
  check_lease(job.check);
  std::vector<UploadedFile> files;
  for (const auto& [name, part] : req.files) {
    if (name == "lease_token" || name == "summary" || name == "next_lease") continue;
    if (name != "files") {
      throw ApiError(422, "form[" + valid_utf8(name.substr(0, 100)) + "]",
                     "unknown form field (expected lease_token, summary, files, next_lease)");
    }
    files.push_back({part.filename, part.content});
  }
  ResultRecord r = intake_result(req.get_file_value("summary").content, job.scene,
                                 job.engine_version, std::move(files));
  const Millis now = now_ms();
  if (next) app.workers.seen(next->worker, now);
  QueueStore::FollowUps follow;
  check_lease(app.store.queue.complete(id, token, r, now, next, &follow));
  spdlog::info("job succeeded id={} status={} class={} artifacts={}", id, r.status,
               r.cls.value_or("-"), r.artifacts.size());
  if (follow.checkpoint) app.store.checkpoints.remove_if_done(id);
  const std::size_t planned =
      app.adaptive.advance_each(app.store, app.limits, follow.adaptive_sweeps, now_ms());
  // The queue was empty for the next lease, but the result let an adaptive sweep plan on: the
  // worker takes one of the new points now rather than after its poll interval.
  if (next && !follow.next && planned > 0) {
    follow.next = app.store.queue.lease(next->worker, next->engine_version, now_ms());
  }
  json answer = {{"job_id", id}, {"state", "succeeded"}, {"status", r.status}};
  if (next) answer["next"] = follow.next ? lease_answer(app, *follow.next, next->worker) : json(nullptr);
  send_json(res, 200, answer);
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
