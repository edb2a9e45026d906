// Checks made on a request's line and headers, before its body is read (cpp-httplib's
// pre-routing and Expect: 100-continue handlers), against the endpoint table:
//   Host    on a loopback server, the Host header names a loopback host (no DNS rebinding);
//   Origin  a write (any method but GET, HEAD, OPTIONS) from a browser comes from this
//           server's own origin: a foreign Origin or Sec-Fetch-Site: cross-site is 403;
//   token   the endpoint's token, 401 when missing, 403 when wrong;
//   length  a write needs Content-Length (411 without one, or for a chunked body) within the
//           endpoint's limit (413);
//   type    JSON endpoints take application/json (but for an empty body), the result upload
//           multipart/form-data (415).
// The connection front (http_front.hpp) runs these checks once a request's head is in; a refused
// request is answered at once and its connection closed: the body is never read.
#pragma once

#include <cstddef>
#include <optional>

#include <httplib.h>

#include "config/options.hpp"
#include "http/http_head.hpp"
#include "input/api_error.hpp"

namespace compaction::server {

struct GuardConfig {
  TokenTable tokens;
  std::size_t max_upload_bytes = 0;  // the result upload's limit
  bool loopback = true;              // the server listens on loopback only
};

GuardConfig guard_config(const ServerOptions& options);

// The reason to refuse the request, or nothing.
std::optional<ApiError> check_request(const httplib::Request& req, const GuardConfig& config);

// The request of a head, as the checks read it (method, decoded path, target, fields).
httplib::Request request_of(const RequestHead& head);

class HttpServer;
void install_request_guard(HttpServer& server, GuardConfig config);

}  // namespace compaction::server
