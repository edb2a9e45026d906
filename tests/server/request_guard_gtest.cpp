// The request guard's checks on a request's line and headers, before any body is read: each
// refusal has its status and names its header; the endpoint table is the one the routes use.
#include "http/request_guard.hpp"

#include <gtest/gtest.h>

#include "http/endpoints.hpp"

using namespace compaction::server;

namespace {

// Tokens, upload limit, loopback.
GuardConfig config() {
  GuardConfig c;
  c.tokens.add({TokenKind::submit, "", "s"}, false);
  c.tokens.add({TokenKind::worker, "", "w"}, false);
  c.max_upload_bytes = 1 << 20;
  c.loopback = true;
  return c;
}

httplib::Request request(const std::string& method, const std::string& path,
                         httplib::Headers headers = {}) {
  httplib::Request r;
  r.method = method;
  r.path = path;
  r.headers = std::move(headers);
  r.headers.emplace("Host", "127.0.0.1:8080");
  return r;
}

httplib::Headers json_with(const std::string& token, std::size_t length = 2) {
  httplib::Headers h = {{"Content-Type", "application/json"},
                        {"Content-Length", std::to_string(length)}};
  if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
  return h;
}

void expect_refused(const httplib::Request& r, int status, const std::string& field) {
  const auto e = check_request(r, config());
  ASSERT_TRUE(e) << r.method << " " << r.path << " was accepted";
  EXPECT_EQ(e->status, status) << e->what();
  EXPECT_EQ(e->field, field) << e->what();
}

}  // namespace

TEST(RequestGuard, AcceptsWhatTheDashboardAndTheWorkersSend) {
  EXPECT_FALSE(check_request(request("GET", "/api/v1/phase-map"), config()));
  EXPECT_FALSE(check_request(request("GET", "/index.html"), config()));
  auto dashboard = request("POST", "/api/v1/sweeps", json_with("s"));
  dashboard.headers.emplace("Origin", "http://127.0.0.1:8080");
  dashboard.headers.emplace("Sec-Fetch-Site", "same-origin");
  EXPECT_FALSE(check_request(dashboard, config()));
  EXPECT_FALSE(check_request(request("POST", "/api/v1/leases", json_with("w")), config()));
  EXPECT_FALSE(check_request(request("POST", "/api/v1/jobs/7/complete",
                                     {{"Content-Type", "multipart/form-data; boundary=x"},
                                      {"Content-Length", "1000"},
                                      {"Authorization", "Bearer w"}}),
                             config()));
}

TEST(RequestGuard, RefusesAForeignOriginOnEveryWrite) {
  auto r = request("POST", "/api/v1/sweeps/1/cancel", json_with("s"));
  r.headers.emplace("Origin", "http://evil.example");
  expect_refused(r, 403, "Origin");
  auto leases = request("POST", "/api/v1/leases", json_with("w"));
  leases.headers.emplace("Sec-Fetch-Site", "cross-site");
  expect_refused(leases, 403, "Origin");
  auto null_origin = request("POST", "/api/v1/sweeps", json_with("s"));
  null_origin.headers.emplace("Origin", "null");
  expect_refused(null_origin, 403, "Origin");
}

TEST(RequestGuard, RefusesAHostThatIsNotLoopbackOnALoopbackServer) {
  auto r = request("GET", "/api/v1/jobs");
  r.headers.erase("Host");
  r.headers.emplace("Host", "rebound.example:8080");
  expect_refused(r, 403, "Host");
  GuardConfig open = config();
  open.loopback = false;  // a server beyond loopback has tokens instead
  EXPECT_FALSE(check_request(r, open));
}

TEST(RequestGuard, ChecksTheTokenFromTheHeadersBeforeTheBody) {
  expect_refused(request("POST", "/api/v1/sweeps", json_with("", 50 << 20)), 401, "Authorization");
  expect_refused(request("POST", "/api/v1/sweeps", json_with("w")), 403, "Authorization");
  expect_refused(request("POST", "/api/v1/jobs/3/heartbeat", json_with("s")), 403, "Authorization");
}

TEST(RequestGuard, RefusesABodyBeyondTheEndpointsLimitOrWithoutALength) {
  expect_refused(request("POST", "/api/v1/sweeps", json_with("s", sweep_body_bytes + 1)), 413, "body");
  expect_refused(request("POST", "/api/v1/leases", json_with("w", small_body_bytes + 1)), 413, "body");
  expect_refused(request("POST", "/api/v1/jobs/1/complete",
                         {{"Content-Type", "multipart/form-data; boundary=x"},
                          {"Content-Length", std::to_string((1 << 20) + 1)},
                          {"Authorization", "Bearer w"}}),
                 413, "body");
  expect_refused(request("GET", "/api/v1/health", {{"Content-Length", "100000"}}), 413, "body");
  auto chunked = request("POST", "/api/v1/sweeps", json_with("s"));
  chunked.headers.emplace("Transfer-Encoding", "chunked");
  expect_refused(chunked, 411, "Content-Length");
  expect_refused(request("POST", "/api/v1/leases", {{"Content-Type", "application/json"},
                                                    {"Authorization", "Bearer w"}}),
                 411, "Content-Length");
  expect_refused(request("POST", "/api/v1/leases",
                         {{"Content-Type", "application/json"}, {"Content-Length", "-1"},
                          {"Authorization", "Bearer w"}}),
                 400, "Content-Length");
}

TEST(RequestGuard, RequiresTheEndpointsContentType) {
  auto text = json_with("s");
  text.erase("Content-Type");
  text.emplace("Content-Type", "text/plain");
  expect_refused(request("POST", "/api/v1/sweeps", text), 415, "Content-Type");
  auto charset = json_with("s");
  charset.erase("Content-Type");
  charset.emplace("Content-Type", "Application/JSON; charset=utf-8");
  EXPECT_FALSE(check_request(request("POST", "/api/v1/sweeps", charset), config()));
  expect_refused(request("POST", "/api/v1/jobs/1/complete", json_with("w")), 415, "Content-Type");
  // An empty body has no type: curl -X POST .../cancel sends Content-Length: 0 and no type.
  EXPECT_FALSE(check_request(request("POST", "/api/v1/sweeps/3/cancel",
                                     {{"Content-Length", "0"}, {"Authorization", "Bearer s"}}),
                             config()));
  expect_refused(request("POST", "/api/v1/sweeps/3/cancel",
                         {{"Content-Length", "2"}, {"Content-Type", "text/plain"}, {"Authorization", "Bearer s"}}),
                 415, "Content-Type");
}

TEST(Endpoints, AreFoundByMethodAndPathAndEverythingElseIsAnotherRequest) {
  EXPECT_EQ(&find_endpoint("POST", "/api/v1/sweeps/12/cancel"), &endpoints::cancel_sweep);
  EXPECT_EQ(&find_endpoint("GET", "/api/v1/jobs/3/artifacts/spacetime.npy"), &endpoints::artifact);
  EXPECT_EQ(&find_endpoint("HEAD", "/api/v1/health"), &endpoints::health);
  EXPECT_EQ(&find_endpoint("GET", "/api/v1/sweeps/x"), &other_request);
  EXPECT_EQ(&find_endpoint("DELETE", "/api/v1/sweeps"), &other_request);
}
