#include "http_util.hpp"

#include <cmath>
#include <cstdlib>

#include <spdlog/spdlog.h>

#include "sqlite.hpp"

namespace compaction::server {

using nlohmann::json;

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(body.dump(), "application/json");
}

void send_error(httplib::Response& res, const ApiError& e) { send_json(res, e.status, e.body()); }

Handler guarded(Handler h) {
  return [h = std::move(h)](const httplib::Request& req, httplib::Response& res) {
    try {
      h(req, res);
    } catch (const ApiError& e) {
      send_error(res, e);
    } catch (const std::exception& e) {
      spdlog::error("{} {} failed: {}", req.method, req.path, e.what());
      send_error(res, ApiError(500, "", std::string("internal error: ") + e.what()));
    }
  };
}

json parse_json_body(const httplib::Request& req) {
  json body = json::parse(req.body, nullptr, false);
  if (body.is_discarded()) throw ApiError(400, "body", "malformed JSON");
  return body;
}

void require_token(const httplib::Request& req, const std::string& expected) {
  if (expected.empty()) return;
  const std::string auth = req.get_header_value("Authorization");
  const std::string prefix = "Bearer ";
  if (auth.empty()) throw ApiError(401, "Authorization", "a Bearer token is required");
  if (auth.rfind(prefix, 0) != 0) {
    throw ApiError(401, "Authorization", "expected \"Authorization: Bearer <token>\"");
  }
  const std::string given = auth.substr(prefix.size());
  // Compare in time independent of where the strings differ.
  unsigned diff = given.size() != expected.size();
  for (std::size_t i = 0; i < given.size(); ++i) {
    diff |= static_cast<unsigned char>(given[i]) ^
            static_cast<unsigned char>(expected[i % expected.size()]);
  }
  if (diff != 0) throw ApiError(403, "Authorization", "wrong token");
}

namespace {
std::optional<long long> to_int(const std::string& s) {
  if (s.empty() || s.size() > 18) return std::nullopt;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}
}  // namespace

std::int64_t path_id(const httplib::Request& req, int match_index, const char* what) {
  const auto v = to_int(req.matches[match_index]);
  if (!v || *v <= 0) throw ApiError(404, "id", std::string("no such ") + what);
  return *v;
}

int query_int(const httplib::Request& req, const char* name, int fallback, int lo, int hi) {
  if (!req.has_param(name)) return fallback;
  const auto v = to_int(req.get_param_value(name));
  if (!v || *v < lo || *v > hi) {
    throw ApiError(422, name, "must be an integer in [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
  }
  return static_cast<int>(*v);
}

std::optional<std::int64_t> query_id(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  const auto v = to_int(req.get_param_value(name));
  if (!v || *v <= 0) throw ApiError(422, name, "must be a positive integer id");
  return *v;
}

std::optional<double> query_number(const httplib::Request& req, const char* name) {
  if (!req.has_param(name)) return std::nullopt;
  const std::string s = req.get_param_value(name);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (s.empty() || end != s.c_str() + s.size() || !std::isfinite(v)) {
    throw ApiError(422, name, "must be a finite number, got \"" + s + "\"");
  }
  return v;
}

std::string body_string(const json& body, const char* key, std::size_t max_len) {
  if (!body.is_object()) throw ApiError(422, "body", "must be a JSON object");
  if (!body.contains(key)) throw ApiError(422, key, "is required");
  if (!body[key].is_string()) throw ApiError(422, key, "must be a string, got " + body[key].dump());
  std::string s = body[key].get<std::string>();
  if (s.empty() || s.size() > max_len) {
    throw ApiError(422, key, "must be 1 to " + std::to_string(max_len) + " characters");
  }
  return s;
}

}  // namespace compaction::server
