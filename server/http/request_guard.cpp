#include "http/request_guard.hpp"

#include <algorithm>
#include <cctype>

#include "http/endpoints.hpp"
#include "http/http_server.hpp"
#include "http/http_util.hpp"

namespace compaction::server {

namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// The host name of a Host header value ("localhost:8080" -> "localhost", "[::1]:80" -> "::1").
std::string host_name(const std::string& host) {
  if (!host.empty() && host.front() == '[') {
    const auto close = host.find(']');
    return close == std::string::npos ? host : host.substr(1, close - 1);
  }
  return host.substr(0, host.find(':'));
}

bool loopback_name(const std::string& name) {
  const std::string n = lower(name);
  return n == "localhost" || n == "localhost." || n == "::1" ||
         (n.rfind("127.", 0) == 0 &&
          n.find_first_not_of("0123456789.") == std::string::npos);
}

bool is_write(const std::string& method) {
  return method != "GET" && method != "HEAD" && method != "OPTIONS";
}

// The media type of a Content-Type value, lower case, without parameters.
std::string media_type(const std::string& content_type) {
  std::string t = lower(content_type.substr(0, content_type.find(';')));
  while (!t.empty() && t.back() == ' ') t.pop_back();
  return t;
}

}  // namespace

GuardConfig guard_config(const ServerOptions& o) {
  return {o.tokens, static_cast<std::size_t>(o.max_upload_mb) << 20,
          is_loopback_host(o.host)};
}

std::optional<ApiError> check_request(const httplib::Request& req, const GuardConfig& c) {
  const Endpoint& e = find_endpoint(req.method, req.path);
  const std::string host = req.get_header_value("Host");
  if (c.loopback && !host.empty() && !loopback_name(host_name(host))) {
    return ApiError(403, "Host", "this server answers only to loopback host names");
  }
  if (is_write(req.method)) {
    if (req.has_header("Origin")) {
      const std::string origin = req.get_header_value("Origin");
      if (origin != "http://" + host && origin != "https://" + host) {
        return ApiError(403, "Origin", "writes are accepted only from this server's own pages");
      }
    }
    if (lower(req.get_header_value("Sec-Fetch-Site")) == "cross-site") {
      return ApiError(403, "Origin", "writes are accepted only from this server's own pages");
    }
  }
  try {
    c.tokens.authenticate(req, e.token);
  } catch (const ApiError& refused) {
    return refused;
  }
  if (req.has_header("Transfer-Encoding")) {
    return ApiError(411, "Content-Length", "send the body with a Content-Length, not chunked");
  }
  // cpp-httplib would read a write without a length until the client closes.
  if (is_write(req.method) && !req.has_header("Content-Length")) {
    return ApiError(411, "Content-Length", "a " + req.method + " needs a Content-Length (0 for no body)");
  }
  const std::size_t limit = e.max_body_bytes == upload_body_bytes ? c.max_upload_bytes
                                                                  : e.max_body_bytes;
  if (req.has_header("Content-Length")) {
    const std::string v = req.get_header_value("Content-Length");
    if (v.empty() || v.size() > 19 || v.find_first_not_of("0123456789") != std::string::npos) {
      return ApiError(400, "Content-Length", "must be a number of bytes");
    }
    if (std::stoull(v) > limit) {
      return ApiError(413, "body", "at most " + std::to_string(limit) + " bytes for " +
                                       req.method + " " + (e.pattern[0] ? "this endpoint" : "this path"));
    }
  }
  const std::string type = media_type(req.get_header_value("Content-Type"));
  // An empty body has no type to check (curl -X POST .../cancel sends none).
  const bool empty = req.get_header_value("Content-Length") == "0";
  if (e.body == BodyKind::json && type != "application/json" && !empty) {
    return ApiError(415, "Content-Type", "must be application/json");
  }
  if (e.body == BodyKind::multipart && type != "multipart/form-data") {
    return ApiError(415, "Content-Type",
                    "must be multipart/form-data with lease_token, summary, files");
  }
  return std::nullopt;
}

httplib::Request request_of(const RequestHead& head) {
  httplib::Request r;
  r.method = head.method;
  r.path = head.path;
  r.target = head.target;
  for (const auto& [name, value] : head.fields) r.headers.emplace(name, value);
  return r;
}

void install_request_guard(HttpServer& server, GuardConfig config) {
  server.set_head_check([config](const RequestHead& head) { return check_request(request_of(head), config); });
}

}  // namespace compaction::server
