#include "api_client.hpp"

#include <httplib.h>

namespace compaction::worker {

using nlohmann::json;

namespace {

Reply to_reply(const httplib::Result& r) {
  Reply out;
  if (!r) {
    out.message = "no answer: " + httplib::to_string(r.error());
    return out;
  }
  out.status = r->status;
  if (!r->body.empty()) out.body = json::parse(r->body, nullptr, false);
  if (out.body.is_discarded()) out.body = nullptr;
  if (out.body.is_object() && out.body.contains("error")) {
    const json& e = out.body["error"];
    out.message = e.value("field", std::string()) + ": " + e.value("message", std::string());
  }
  if (r->status == 200 || r->status == 201) {
    out.outcome = Outcome::ok;
  } else if (r->status == 204) {
    out.outcome = Outcome::empty;
  } else if (r->status == 409) {
    out.outcome = Outcome::lease_lost;
  } else if (r->status == 404) {
    out.outcome = Outcome::not_found;
  } else if (r->status >= 400 && r->status < 500) {
    out.outcome = Outcome::rejected;
  } else {
    out.outcome = Outcome::unreachable;
    if (out.message.empty()) out.message = "HTTP " + std::to_string(r->status);
  }
  return out;
}

httplib::Headers auth_headers(const std::string& token) {
  httplib::Headers h;
  if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
  return h;
}

// Timeouts, and TCP_NODELAY: httplib writes a request's headers and its body in separate
// sends, and without it the body waits for the server's delayed ACK (40 ms on Linux) before
// it leaves, on every request that has a body.
void configure(httplib::Client& c) {
  c.set_tcp_nodelay(true);
  c.set_connection_timeout(5, 0);
  c.set_read_timeout(120, 0);
  c.set_write_timeout(120, 0);
}

httplib::Client make_client(const std::string& base) {
  httplib::Client c(base);
  configure(c);
  return c;
}

}  // namespace

ApiClient::ApiClient(std::string base_url, std::string token)
    : base_url_(std::move(base_url)), token_(std::move(token)) {}

ApiClient::~ApiClient() = default;

Reply ApiClient::post_json(const std::string& path, const json& body) {
  auto c = make_client(base_url_);
  const httplib::Headers h = auth_headers(token_);
  return to_reply(c.Post(path.c_str(), h, body.dump(), "application/json"));
}

Reply ApiClient::lease(const std::string& worker, const std::string& engine_version) {
  {
    const std::lock_guard lock(next_mutex_);
    if (next_) {
      Reply r = std::move(*next_);
      next_.reset();
      return r;
    }
  }
  return post_json("/api/v1/leases", {{"worker", worker}, {"engine_version", engine_version}});
}

Reply ApiClient::heartbeat(std::int64_t job_id, const std::string& lease_token, double eps,
                          const json& resumed) {
  json body = {{"lease_token", lease_token}, {"eps", eps}};
  if (!resumed.is_null()) body["resumed"] = resumed;
  return post_json("/api/v1/jobs/" + std::to_string(job_id) + "/heartbeat", body);
}

Reply ApiClient::complete(std::int64_t job_id, const std::string& lease_token,
                          const std::string& summary, const std::vector<UploadFile>& files,
                          const std::optional<NextLease>& next) {
  auto c = make_client(base_url_);
  const httplib::Headers h = auth_headers(token_);
  httplib::MultipartFormDataItems items = {
      {"lease_token", lease_token, "", "text/plain"},
      {"summary", summary, "summary.json", "application/json"},
  };
  if (next) {
    const json ask = {{"worker", next->worker}, {"engine_version", next->engine_version}};
    items.push_back({"next_lease", ask.dump(), "", "application/json"});
  }
  for (const auto& f : files) items.push_back({"files", f.data, f.name, "application/octet-stream"});
  Reply r = to_reply(c.Post(("/api/v1/jobs/" + std::to_string(job_id) + "/complete").c_str(), h, items));
  if (next && r.outcome == Outcome::ok && r.body.is_object() && r.body.contains("next")) {
    // The lease as POST /leases would have answered it: 200 with the job, or 204.
    Reply lease;
    if (r.body["next"].is_object()) {
      lease.outcome = Outcome::ok;
      lease.status = 200;
      lease.body = r.body["next"];
    } else {
      lease.outcome = Outcome::empty;
      lease.status = 204;
    }
    const std::lock_guard lock(next_mutex_);
    next_ = std::move(lease);
  }
  return r;
}

void ApiClient::release_unclaimed() {
  std::optional<Reply> held;
  {
    const std::lock_guard lock(next_mutex_);
    held.swap(next_);
  }
  if (!held || held->outcome != Outcome::ok) return;
  const auto id = held->body.value("job_id", std::int64_t{0});
  const auto token = held->body.value("lease_token", std::string());
  if (id > 0) release(id, token);
}

Reply ApiClient::fail(std::int64_t job_id, const std::string& lease_token,
                      const std::string& reason, bool retryable) {
  return post_json("/api/v1/jobs/" + std::to_string(job_id) + "/fail",
                   {{"lease_token", lease_token}, {"reason", reason}, {"retryable", retryable}});
}

Reply ApiClient::release(std::int64_t job_id, const std::string& lease_token) {
  return post_json("/api/v1/jobs/" + std::to_string(job_id) + "/release",
                   {{"lease_token", lease_token}});
}

Reply ApiClient::upload_checkpoint(std::int64_t job_id, const std::string& lease_token,
                                  std::int64_t step, double eps, const std::string& bytes) {
  auto c = make_client(base_url_);
  const httplib::Headers h = auth_headers(token_);
  const httplib::MultipartFormDataItems items = {
      {"lease_token", lease_token, "", "text/plain"},
      {"step", std::to_string(step), "", "text/plain"},
      {"eps", json(eps).dump(), "", "text/plain"},
      {"checkpoint", bytes, "checkpoint.bin", "application/octet-stream"},
  };
  return to_reply(
      c.Post(("/api/v1/jobs/" + std::to_string(job_id) + "/checkpoint").c_str(), h, items));
}

Reply ApiClient::download_checkpoint(std::int64_t job_id, std::string& bytes) {
  auto c = make_client(base_url_);
  const httplib::Headers h = auth_headers(token_);
  const auto r = c.Get(("/api/v1/jobs/" + std::to_string(job_id) + "/checkpoint").c_str(), h);
  if (r && r->status == 200) {
    Reply out;
    out.outcome = Outcome::ok;
    out.status = 200;
    bytes = r->body;
    return out;
  }
  return to_reply(r);
}

}  // namespace compaction::worker
