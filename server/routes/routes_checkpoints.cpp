// POST /api/v1/jobs/{id}/checkpoint (multipart: lease_token, step, eps, checkpoint): a worker
// stores the checkpoint of the run it holds the lease of; GET /api/v1/jobs/{id}/checkpoint: the
// bytes, for the worker that leases the job next (docs/service.md, "Checkpoints"). Both need
// the worker token; the upload needs the live lease token too (409 otherwise).
#include "routes/checkpoint_routes.hpp"

#include <charconv>
#include <cmath>

#include <spdlog/spdlog.h>

#include "http/endpoints.hpp"
#include "http/http_util.hpp"
#include "input/json_input.hpp"
#include "input/safe_text.hpp"
#include "store/clock.hpp"
#include "views/checkpoint_views.hpp"

namespace compaction::server {

using nlohmann::json;

namespace {

// A form field's text as a whole decimal integer >= 0.
std::int64_t form_step(const std::string& text) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || end != text.data() + text.size() || text.empty() || v < 0) {
    throw ApiError(422, "step", "must be an integer >= 0, got " + describe(json(valid_utf8(text.substr(0, 40)))));
  }
  return v;
}

// A form field's text as a decimal number in [0, 1] (decimal_number: no spaces, no hex).
double form_eps(const std::string& text) {
  const auto v = decimal_number(text);
  if (!v || *v < 0.0 || *v > 1.0) {
    throw ApiError(422, "eps", "must be a decimal number in [0, 1], got " + describe(json(valid_utf8(text.substr(0, 40)))));
  }
  return *v;
}

void check(LeaseCheck c) {
  if (c == LeaseCheck::unknown_job) throw ApiError(404, "id", "no such job");
  if (c == LeaseCheck::lost) {
    throw ApiError(409, "lease_token",
                   "the lease is not live (expired, released, cancelled or never held)");
  }
}

void upload(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  for (const auto& [name, part] : req.files) {
    if (name != "lease_token" && name != "step" && name != "eps" && name != "checkpoint") {
      throw ApiError(422, "form[" + valid_utf8(name.substr(0, 100)) + "]",
                     "unknown form field (expected lease_token, step, eps, checkpoint)");
    }
  }
  for (const char* field : {"lease_token", "step", "eps", "checkpoint"}) {
    if (!req.has_file(field)) throw ApiError(422, field, "is required");
  }
  const std::string token = req.get_file_value("lease_token").content;
  const std::int64_t step = form_step(req.get_file_value("step").content);
  const double eps = form_eps(req.get_file_value("eps").content);
  const std::string& bytes = req.get_file_value("checkpoint").content;
  if (bytes.empty()) throw ApiError(422, "checkpoint", "is empty");
  check(app.store.queue.check_lease(id, token));  // before the file is written
  check(app.store.checkpoints.put(id, token, bytes, step, eps, now_ms()));
  spdlog::info("checkpoint stored id={} step={} eps={:.6g} bytes={}", id, step, eps, bytes.size());
  send_json(res, 200, {{"job_id", id},
                       {"size", static_cast<std::int64_t>(bytes.size())},
                       {"step", step},
                       {"eps", eps}});
}

void download(App& app, const httplib::Request& req, httplib::Response& res) {
  const std::int64_t id = path_id(req, 1, "job");
  const auto c = app.store.checkpoints.find(id);
  if (!c) throw ApiError(404, "checkpoint", "job " + std::to_string(id) + " has no checkpoint");
  res.status = 200;
  res.set_content(app.store.checkpoints.read(*c), "application/octet-stream");
}

}  // namespace

std::optional<ResumeReport> parse_resume_report(const json& body) {
  if (!body.contains("resumed")) return std::nullopt;
  const json& r = body["resumed"];
  if (!r.is_object()) throw ApiError(422, "resumed", "must be an object {step, eps}");
  for (const auto& [key, value] : r.items()) {
    if (key != "step" && key != "eps") {
      throw ApiError(422, "resumed." + valid_utf8(key.substr(0, 100)), "unknown key");
    }
  }
  ResumeReport out;
  const auto step = r.contains("step") ? as_int64(r["step"]) : std::nullopt;
  if (!step || *step < 0) {
    throw ApiError(422, "resumed.step",
                   "must be an integer >= 0, got " + describe(r.value("step", json())));
  }
  out.step = *step;
  if (!r.contains("eps") || !r["eps"].is_number() || !std::isfinite(r["eps"].get<double>()) ||
      r["eps"].get<double>() < 0.0 || r["eps"].get<double>() > 1.0) {
    throw ApiError(422, "resumed.eps",
                   "must be a number in [0, 1], got " + describe(r.value("eps", json())));
  }
  out.eps = r["eps"].get<double>();
  return out;
}

json checkpoint_of(App& app, std::int64_t job_id) {
  const auto c = app.store.checkpoints.find(job_id);
  return c ? views::checkpoint(*c) : json(nullptr);
}

void add_checkpoint_detail(App& app, std::int64_t job_id, json& detail) {
  detail["checkpoint"] = checkpoint_of(app, job_id);
  detail["resumes"] = views::resumes(app.store.checkpoints.resumes(job_id));
}

void register_checkpoint_routes(httplib::Server& server, App& app) {
  using namespace std::placeholders;
  add_route(server, endpoints::put_checkpoint, std::bind(upload, std::ref(app), _1, _2));
  add_route(server, endpoints::get_checkpoint, std::bind(download, std::ref(app), _1, _2));
}

}  // namespace compaction::server
