// Every endpoint of the REST API with what it asks of a request before its body is read: the
// token, the body's content type and the most bytes it may hold. The routes register their
// handlers through this table (add_route) and the request guard checks requests against it,
// so a rule of an endpoint lives here and nowhere else.
#pragma once

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <httplib.h>

#include "config/tokens.hpp"
#include "http/http_util.hpp"

namespace compaction::server {

enum class BodyKind { none, json, multipart };

struct Endpoint {
  const char* method;   // "GET", "POST", "PUT" or "DELETE"
  const char* pattern;  // cpp-httplib's regex of the path
  TokenKind token;
  BodyKind body;
  std::size_t max_body_bytes;  // upload_body_bytes: the server's --max-upload-mb
};

// Body limits. A request without a body may still carry a few bytes (some clients send "{}").
inline constexpr std::size_t no_body_bytes = 4 << 10;
// Lease, heartbeat, release: a few hundred bytes; fail: a reason of up to 20 000 characters,
// each escaped to at most 6 bytes of JSON.
inline constexpr std::size_t small_body_bytes = 256 << 10;
// A sweep: 2 000 explicit points take about 100 kB.
inline constexpr std::size_t sweep_body_bytes = 1 << 20;
inline constexpr std::size_t upload_body_bytes = std::numeric_limits<std::size_t>::max();

namespace endpoints {
// clang-format off
inline constexpr Endpoint create_sweep  {"POST", "/api/v1/sweeps",                      TokenKind::submit, BodyKind::json,      sweep_body_bytes};
inline constexpr Endpoint list_sweeps   {"GET",  "/api/v1/sweeps",                      TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint show_sweep    {"GET",  R"(/api/v1/sweeps/(\d+))",             TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint cancel_sweep  {"POST", R"(/api/v1/sweeps/(\d+)/cancel)",      TokenKind::submit, BodyKind::json,      no_body_bytes};
inline constexpr Endpoint export_sweep  {"GET",  R"(/api/v1/sweeps/(\d+)/export)",      TokenKind::none,   BodyKind::none,      no_body_bytes};
// Writes nothing: no token; a sweep's body, as create_sweep.
inline constexpr Endpoint estimate_sweep{"POST", "/api/v1/sweeps/estimate",             TokenKind::none,   BodyKind::json,      sweep_body_bytes};
inline constexpr Endpoint sweep_plan    {"GET",  R"(/api/v1/sweeps/(\d+)/plan)",        TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint list_jobs     {"GET",  "/api/v1/jobs",                        TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint show_job      {"GET",  R"(/api/v1/jobs/(\d+))",               TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint list_artifacts{"GET",  R"(/api/v1/jobs/(\d+)/artifacts)",     TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint artifact      {"GET",  R"(/api/v1/jobs/(\d+)/artifacts/([^/]+))", TokenKind::none, BodyKind::none,    no_body_bytes};
inline constexpr Endpoint phase_map     {"GET",  "/api/v1/phase-map",                   TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint phase_regions {"GET",  "/api/v1/phase-map/regions",           TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint lease         {"POST", "/api/v1/leases",                      TokenKind::worker, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint heartbeat     {"POST", R"(/api/v1/jobs/(\d+)/heartbeat)",     TokenKind::worker, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint complete      {"POST", R"(/api/v1/jobs/(\d+)/complete)",      TokenKind::worker, BodyKind::multipart, upload_body_bytes};
inline constexpr Endpoint fail          {"POST", R"(/api/v1/jobs/(\d+)/fail)",          TokenKind::worker, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint release       {"POST", R"(/api/v1/jobs/(\d+)/release)",       TokenKind::worker, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint put_checkpoint{"POST", R"(/api/v1/jobs/(\d+)/checkpoint)",    TokenKind::worker, BodyKind::multipart, upload_body_bytes};
inline constexpr Endpoint get_checkpoint{"GET",  R"(/api/v1/jobs/(\d+)/checkpoint)",    TokenKind::worker, BodyKind::none,      no_body_bytes};
inline constexpr Endpoint health        {"GET",  "/api/v1/health",                      TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint metrics       {"GET",  "/metrics",                            TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint api_metrics   {"GET",  "/api/v1/metrics",                     TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint openapi       {"GET",  "/api/v1/openapi.yaml",                TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint presets       {"GET",  "/api/v1/presets",                     TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint limits        {"GET",  "/api/v1/limits",                      TokenKind::none,   BodyKind::none,      no_body_bytes};
// Human labels (routes_labels.cpp) and imports of another server's export (routes_imports.cpp).
inline constexpr Endpoint set_label     {"PUT",  R"(/api/v1/jobs/(\d+)/label)",         TokenKind::submit, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint clear_label   {"DELETE", R"(/api/v1/jobs/(\d+)/label)",       TokenKind::submit, BodyKind::json,      small_body_bytes};
inline constexpr Endpoint show_label    {"GET",  R"(/api/v1/jobs/(\d+)/label)",         TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint label_audit   {"GET",  "/api/v1/labels/audit",                TokenKind::none,   BodyKind::none,      no_body_bytes};
inline constexpr Endpoint import_sweep  {"POST", "/api/v1/imports",                     TokenKind::submit, BodyKind::json,      upload_body_bytes};
// clang-format on
}  // namespace endpoints

// Any other request (the dashboard's static files, unknown paths): no token, no body.
inline constexpr Endpoint other_request{"", "", TokenKind::none, BodyKind::none, no_body_bytes};

// The endpoint a request's method and path name, or other_request.
const Endpoint& find_endpoint(const std::string& method, const std::string& path);

// Registers the handler (inside guarded()) for the endpoint's method and pattern.
void add_route(httplib::Server& server, const Endpoint& e, Handler handler);

// The same for a handler that reads the body itself, as it arrives (a POST or PUT).
using StreamingHandler = std::function<void(const httplib::Request&, httplib::Response&,
                                            const httplib::ContentReader&)>;
void add_streaming_route(httplib::Server& server, const Endpoint& e, StreamingHandler handler);

}  // namespace compaction::server
