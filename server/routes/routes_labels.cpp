// Human labels: PUT /api/v1/jobs/{id}/label sets a person's label on a run with a reason,
// DELETE removes it (the classifier's is the run's label again), GET shows it with the run's
// history, GET /api/v1/labels/audit lists every change. Writes need the submit token (checked
// by the request guard before the body is read).
#include <spdlog/spdlog.h>

#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "http/page_limits.hpp"
#include "input/safe_text.hpp"
#include "routes/app.hpp"
#include "store/clock.hpp"
#include "views/label_views.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// Only these keys; anything else is a 422 naming it.
void only_keys(const json& body, std::initializer_list<const char*> keys) {
  if (!body.is_object()) throw ApiError(422, "body", "must be a JSON object");
  for (const auto& [key, value] : body.items()) {
    bool known = false;
    for (const char* k : keys) known |= key == k;
    if (!known) throw ApiError(422, valid_utf8(key.substr(0, 100)), "unknown key");
  }
}

std::string class_label(const json& body) {
  if (!body.contains("label")) throw ApiError(422, "label", "is required");
  const json& l = body["label"];
  if (!l.is_string() || l.get<std::string>().size() != 1 ||
      std::string("abcdef").find(l.get<std::string>()) == std::string::npos) {
    throw ApiError(422, "label", "must be one of a, b, c, d, e, f, got " + describe(l));
  }
  return l.get<std::string>();
}

void check_outcome(LabelOutcome o) {
  switch (o) {
    case LabelOutcome::ok: return;
    case LabelOutcome::unknown_job: throw ApiError(404, "id", "no such job");
    case LabelOutcome::no_result:
      throw ApiError(409, "id", "the job has no result yet: there is no label to disagree with");
    case LabelOutcome::not_labelled: throw ApiError(404, "label", "the job has no human label");
  }
}

// The run's labels: the human's, the classifier's, and the run's changes (newest first).
json labels_of(App& app, std::int64_t id) {
  const auto j = app.store.reads.job(id);
  if (!j) throw ApiError(404, "id", "no such job");
  std::int64_t total = 0;
  const auto history = app.store.labels.audit(id, 1000, 0, total);
  json out = views::label_audit(history, total, 1000, 0);
  out.erase("limit");
  out.erase("offset");
  const auto& r = j->job.result;
  out["job_id"] = id;
  out["human_label"] = views::human_label(j->job.human_label);
  out["classifier"] = r ? json{{"class", r->cls ? json(*r->cls) : json(nullptr)},
                               {"confidence", r->confidence ? json(*r->confidence) : json(nullptr)},
                               {"runner_up", r->runner_up ? json(*r->runner_up) : json(nullptr)}}
                        : json(nullptr);
  return out;
}

}  // namespace

void register_label_routes(httplib::Server& server, App& app) {
  add_route(server, endpoints::set_label, [&app](const httplib::Request& req, httplib::Response& res) {
    const std::int64_t id = path_id(req, 1, "job");
    const json body = parse_json_body(req);
    only_keys(body, {"label", "reason", "by"});
    HumanLabel l;
    l.label = class_label(body);
    l.reason = body_string(body, "reason", kLabelReasonMaxBytes, TextKind::prose);
    l.by = body_string(body, "by", kLabelByMaxBytes);
    l.at = now_ms();
    l.token = app.options.tokens.identity(req, endpoints::set_label.token);
    check_outcome(app.store.labels.set(id, l));
    spdlog::info("label set job={} label={} by=\"{}\" token={}", id, l.label, log_escape(l.by),
                 l.token);
    app.adaptive.job_ended(app.store, app.limits, id, now_ms());
    send_json(res, 200, labels_of(app, id));
  });

  add_route(server, endpoints::clear_label, [&app](const httplib::Request& req, httplib::Response& res) {
    const std::int64_t id = path_id(req, 1, "job");
    const json body = parse_json_body(req);
    only_keys(body, {"reason", "by"});
    const std::string by = body_string(body, "by", kLabelByMaxBytes);
    const std::string reason =
        body.contains("reason") ? body_string(body, "reason", kLabelReasonMaxBytes, TextKind::prose)
                                : std::string();
    const std::string token = app.options.tokens.identity(req, endpoints::clear_label.token);
    check_outcome(app.store.labels.clear(id, reason, by, token, now_ms()));
    spdlog::info("label cleared job={} by=\"{}\" token={}", id, log_escape(by), token);
    app.adaptive.job_ended(app.store, app.limits, id, now_ms());
    send_json(res, 200, labels_of(app, id));
  });

  add_route(server, endpoints::show_label, [&app](const httplib::Request& req, httplib::Response& res) {
    send_json(res, 200, labels_of(app, path_id(req, 1, "job")));
  });

  add_route(server, endpoints::label_audit, [&app](const httplib::Request& req, httplib::Response& res) {
    const auto job = query_id(req, "job");
    const int limit = query_int(req, "limit", kDefaultPageRows, 1, kMaxPageRows);
    const int offset = query_int(req, "offset", 0, 0, kMaxOffset);
    std::int64_t total = 0;
    const auto changes = app.store.labels.audit(job, limit, offset, total);
    send_json(res, 200, views::label_audit(changes, total, limit, offset));
  });
}

}  // namespace compaction::server
