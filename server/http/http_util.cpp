#include "http/http_util.hpp"

#include <atomic>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <spdlog/spdlog.h>

#include "input/json_input.hpp"
#include "input/safe_text.hpp"

namespace compaction::server {

using nlohmann::json;

std::string json_text(const json& body) {
  return body.dump(-1, ' ', false, json::error_handler_t::replace);
}

void send_json(httplib::Response& res, int status, const json& body) {
  res.status = status;
  res.set_content(json_text(body), "application/json");
}

std::string new_error_id() {
  static std::atomic<unsigned> counter{0};
  const auto t = std::chrono::duration_cast<std::chrono::milliseconds>(
                     std::chrono::system_clock::now().time_since_epoch())
                     .count();
  char buf[32];
  std::snprintf(buf, sizeof buf, "e%llx-%x", static_cast<unsigned long long>(t),
                counter.fetch_add(1) & 0xffffu);
  return buf;
}

void send_internal_error(const httplib::Request& req, httplib::Response& res,
                         const std::string& what) {
  const std::string id = new_error_id();
  spdlog::error("internal error id={} {} {}: {}", id, req.method, log_escape(req.path),
                log_escape(what, 2000));
  json body = ApiError(500, "", "internal error").body();
  body["error"]["id"] = id;
  send_json(res, 500, body);
}

void send_error(httplib::Response& res, const ApiError& e) { send_json(res, e.status, e.body()); }

Handler guarded(Handler h) {
  return [h = std::move(h)](const httplib::Request& req, httplib::Response& res) {
    try {
      h(req, res);
    } catch (const ApiError& e) {
      send_error(res, e);
    } catch (const std::exception& e) {
      send_internal_error(req, res, e.what());
    } catch (...) {
      send_internal_error(req, res, "unknown exception");
    }
  };
}

json parse_json_body(const httplib::Request& req) { return parse_client_json(req.body, "body"); }

namespace {
std::optional<long long> to_int(const std::string& s) {
  if (s.empty() || s.size() > 18) return std::nullopt;
  char* end = nullptr;
  const long long v = std::strtoll(s.c_str(), &end, 10);
  if (end != s.c_str() + s.size()) return std::nullopt;
  return v;
}

}  // namespace

std::optional<double> decimal_number(const std::string& s) {
  double v = 0;
  const char* end = s.data() + s.size();
  const auto [ptr, ec] = std::from_chars(s.data(), end, v);
  if (s.empty() || ec != std::errc() || ptr != end || !std::isfinite(v)) return std::nullopt;
  return v;
}

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
  const auto v = decimal_number(s);
  if (!v) throw ApiError(422, name, "must be a finite number, got " + describe(json(valid_utf8(s))));
  return *v;
}

std::string body_string(const json& body, const char* key, std::size_t max_len, TextKind text) {
  if (!body.is_object()) throw ApiError(422, "body", "must be a JSON object");
  if (!body.contains(key)) throw ApiError(422, key, "is required");
  if (!body[key].is_string()) {
    throw ApiError(422, key, "must be a string, got " + describe(body[key]));
  }
  std::string s = body[key].get<std::string>();
  if (s.empty() || s.size() > max_len) {
    throw ApiError(422, key, "must be 1 to " + std::to_string(max_len) + " bytes");
  }
  if (text == TextKind::name && has_control_characters(s)) {
    throw ApiError(422, key, "must not hold control characters");
  }
  if (text == TextKind::prose && has_control_characters(s, true)) {
    throw ApiError(422, key, "must be UTF-8 text without control characters but newlines and tabs");
  }
  return s;
}

}  // namespace compaction::server
