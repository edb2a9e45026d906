// The REST API in process on a loopback port: every bad input gets its status code and a JSON
// error naming the field, and leaves the database exactly as it was; tokens are enforced;
// the lease cycle works over HTTP with multipart uploads.
#include <gtest/gtest.h>

#include <thread>

#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "compaction/result.hpp"
#include "http/endpoints.hpp"
#include "loopback_api.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

struct ApiTest : LoopbackApi {
  void configure_app(App& a) override { a.limits.max_points = 50; }

  std::int64_t create_sweep() {
    auto r = post("/api/v1/sweeps",
                  R"({"name": "demo", "points": [{"S": 0.05, "R": 0.001, "phi": 0.4}],
                      "numerics": {"cells_per_unit": 8, "eps_end": 0.05}})",
                  submit);
    EXPECT_EQ(r->status, 201) << r->body;
    return json::parse(r->body)["id"];
  }
  json lease() {
    auto r = post("/api/v1/leases",
                  json{{"worker", "w1"}, {"engine_version", compaction::engine_version()}}.dump(),
                  worker);
    EXPECT_EQ(r->status, 200);
    return json::parse(r->body);
  }
};

struct BadCase {
  std::string what, method, path, body, token;
  int status;
  std::string field;
};

}  // namespace

TEST_F(ApiTest, EveryBadInputIsAnsweredWithItsStatusAndFieldAndChangesNothing) {
  create_sweep();
  const json l = lease();
  const std::string job = "/api/v1/jobs/" + std::to_string(l["job_id"].get<int>());
  const std::string tok = l["lease_token"];
  const std::string pt = R"("points": [{"S": 0.05, "R": 0.001, "phi": 0.4}])";
  const std::vector<BadCase> cases = {
      {"malformed JSON", "POST", "/api/v1/sweeps", "{\"name\": ", submit, 400, "body"},
      {"NaN literal", "POST", "/api/v1/sweeps", R"({"name": "x", "points": [{"S": NaN, "R": 0.001, "phi": 0.4}]})", submit, 400, "body"},
      {"number overflowing a double", "POST", "/api/v1/sweeps", R"({"name": "x", "points": [{"S": 1e999, "R": 0.001, "phi": 0.4}]})", submit, 400, "body"},
      {"wrong type", "POST", "/api/v1/sweeps", R"({"name": 5, )" + pt + "}", submit, 422, "name"},
      {"S out of range", "POST", "/api/v1/sweeps", R"({"name": "x", "points": [{"S": 2, "R": 0.001, "phi": 0.4}]})", submit, 422, "points[0].S"},
      {"R out of range", "POST", "/api/v1/sweeps", R"({"name": "x", "points": [{"S": 0.1, "R": 0, "phi": 0.4}]})", submit, 422, "points[0].R"},
      {"phi out of range", "POST", "/api/v1/sweeps", R"({"name": "x", "S": 0.1, "R": 0.001, "phi": [0.4, 0.99]})", submit, 422, "phi"},
      {"oversized sweep", "POST", "/api/v1/sweeps", R"({"name": "x", "S": {"min": 0.01, "max": 0.1, "n": 10}, "R": {"min": 0.001, "max": 0.01, "n": 10}, "phi": 0.4})", submit, 413, "S"},
      {"unknown key", "POST", "/api/v1/sweeps", R"({"name": "x", "colour": "red", )" + pt + "}", submit, 422, "colour"},
      {"missing token", "POST", "/api/v1/sweeps", R"({"name": "x", )" + pt + "}", "", 401, "Authorization"},
      {"wrong token", "POST", "/api/v1/sweeps", R"({"name": "x", )" + pt + "}", worker, 403, "Authorization"},
      {"unknown sweep", "GET", "/api/v1/sweeps/999", "", "", 404, "id"},
      {"unknown sweep cancel", "POST", "/api/v1/sweeps/999/cancel", "", submit, 404, "id"},
      {"cancel without token", "POST", "/api/v1/sweeps/1/cancel", "", "", 401, "Authorization"},
      {"unknown job", "GET", "/api/v1/jobs/999", "", "", 404, "id"},
      {"bad state filter", "GET", "/api/v1/jobs?state=done", "", "", 422, "state"},
      {"bad phi filter", "GET", "/api/v1/jobs?phi=abc", "", "", 422, "phi"},
      {"bad limit", "GET", "/api/v1/jobs?limit=0", "", "", 422, "limit"},
      {"phase map without phi", "GET", "/api/v1/phase-map", "", "", 422, "phi"},
      {"phase map NaN phi", "GET", "/api/v1/phase-map?phi=nan", "", "", 422, "phi"},
      {"phase map bad numerics filter", "GET", "/api/v1/phase-map?phi=0.4&cells_per_unit=x", "", "", 422, "cells_per_unit"},
      {"regions without phi", "GET", "/api/v1/phase-map/regions", "", "", 422, "phi"},
      {"regions phi out of range", "GET", "/api/v1/phase-map/regions?phi=0.9", "", "", 422, "phi"},
      {"regions grid too fine", "GET", "/api/v1/phase-map/regions?phi=0.4&grid=1000", "", "", 422, "grid"},
      {"regions numerics filter below the range", "GET", "/api/v1/phase-map/regions?phi=0.4&cells_per_unit=1", "", "", 422, "cells_per_unit"},
      {"regions bad sweep", "GET", "/api/v1/phase-map/regions?phi=0.4&sweep=0", "", "", 422, "sweep"},
      {"estimate S out of range", "POST", "/api/v1/sweeps/estimate", R"({"name": "x", "points": [{"S": 2, "R": 0.001, "phi": 0.4}]})", "", 422, "points[0].S"},
      {"unknown artifact", "GET", job + "/artifacts/spacetime.npy", "", "", 404, "name"},
      {"bad export format", "GET", "/api/v1/sweeps/1/export?format=xml", "", "", 422, "format"},
      {"bad export artifacts", "GET", "/api/v1/sweeps/1/export?format=archive&artifacts=some", "", "", 422, "artifacts"},
      {"export artifacts without archive", "GET", "/api/v1/sweeps/1/export?format=csv&artifacts=none", "", "", 422, "artifacts"},
      {"lease without worker token", "POST", "/api/v1/leases", R"({"worker": "w", "engine_version": "x"})", submit, 403, "Authorization"},
      {"lease without worker name", "POST", "/api/v1/leases", R"({"engine_version": "x"})", worker, 422, "worker"},
      {"heartbeat stale token", "POST", job + "/heartbeat", R"({"lease_token": "stale", "eps": 0.01})", worker, 409, "lease_token"},
      {"heartbeat missing token", "POST", job + "/heartbeat", R"({"eps": 0.01})", worker, 422, "lease_token"},
      {"heartbeat bad eps", "POST", job + "/heartbeat", json{{"lease_token", tok}, {"eps", "x"}}.dump(), worker, 422, "eps"},
      {"heartbeat unknown job", "POST", "/api/v1/jobs/999/heartbeat", json{{"lease_token", tok}}.dump(), worker, 404, "id"},
      {"fail stale token", "POST", job + "/fail", R"({"lease_token": "stale", "reason": "x"})", worker, 409, "lease_token"},
      {"fail without reason", "POST", job + "/fail", json{{"lease_token", tok}}.dump(), worker, 422, "reason"},
      {"fail bad retryable", "POST", job + "/fail", json{{"lease_token", tok}, {"reason", "x"}, {"retryable", "yes"}}.dump(), worker, 422, "retryable"},
      {"release stale token", "POST", job + "/release", R"({"lease_token": "stale"})", worker, 409, "lease_token"},
      {"complete not multipart", "POST", job + "/complete", json{{"lease_token", tok}}.dump(), worker, 415, "Content-Type"},
      {"unknown path", "GET", "/api/v1/nothing", "", "", 404, "path"},
      {"invalid UTF-8 in the path", "GET", "/%FF", "", "", 404, "path"},
      {"invalid UTF-8 in an API path", "POST", "/api/v1/x%C3%28", "{}", "", 404, "path"},
      {"invalid UTF-8 in a query", "GET", "/api/v1/phase-map?phi=%FF", "", "", 422, "phi"},
      {"a hexadecimal query number", "GET", "/api/v1/jobs?phi=0x10", "", "", 422, "phi"},
      {"NUL in a name", "POST", "/api/v1/sweeps", R"({"name": "a\u0000b", )" + pt + "}", submit, 422, "name"},
      {"escape codes in a name", "POST", "/api/v1/sweeps", R"({"name": "\u001b[2Jx", )" + pt + "}", submit, 422, "name"},
      {"newline in a worker name", "POST", "/api/v1/leases", R"({"worker": "w\nforged", "engine_version": "x"})", worker, 422, "worker"},
      {"70 000 levels of nesting", "POST", "/api/v1/sweeps", "{\"name\": " + std::string(70000, '[') + std::string(70000, ']') + ", \"points\": []}", submit, 400, "body"},
      {"deep numerics", "POST", "/api/v1/sweeps", "{\"name\": \"x\", \"numerics\": " + std::string(100, '[') + std::string(100, ']') + "}", submit, 400, "body"},
      {"deep heartbeat eps", "POST", job + "/heartbeat", "{\"lease_token\": \"x\", \"eps\": " + std::string(100, '[') + std::string(100, ']') + "}", worker, 400, "body"},
      {"a cancel with arguments", "POST", "/api/v1/sweeps/1/cancel", R"({"now": true})", submit, 422, "now"},
      {"the solid column", "POST", "/api/v1/sweeps", R"({"name": "x", "points": [{"S": 0.05, "R": 0.001, "phi": 1.0}]})", submit, 422, "points[0].phi"},
      {"more snapshots than an upload can take", "POST", "/api/v1/sweeps", R"({"name": "x", )" + pt + R"(, "numerics": {"snapshot_eps": [)" + [] { std::string v; for (int i = 0; i < 100; ++i) v += (i ? ", " : "") + std::to_string(0.005 * (i + 1)); return v; }() + "], \"cells_per_unit\": 40}}", submit, 422, "numerics.snapshot_eps"},
  };
  const std::string before = store->reads.fingerprint();
  for (const BadCase& c : cases) {
    httplib::Headers h;
    if (!c.token.empty()) h = auth(c.token);
    auto r = c.method == "GET" ? client->Get(c.path.c_str(), h)
                               : client->Post(c.path.c_str(), h, c.body, "application/json");
    ASSERT_TRUE(r) << c.what;
    EXPECT_EQ(r->status, c.status) << c.what << ": " << r->body;
    const json body = json::parse(r->body, nullptr, false);
    ASSERT_TRUE(body.is_object()) << c.what << ": " << r->body;
    EXPECT_EQ(body["error"]["field"], c.field) << c.what << ": " << r->body;
    EXPECT_FALSE(body["error"]["message"].get<std::string>().empty()) << c.what;
    EXPECT_EQ(store->reads.fingerprint(), before) << c.what << " changed the database";
  }
}

// Node 18's FormData ends its body at the close delimiter; the library's parser wants the CRLF
// that curl and compaction-worker send after it. The refusal says so, and stores nothing.
TEST_F(ApiTest, AnUploadEndingAtItsCloseDelimiterIsRefusedWithAReasonAndChangesNothing) {
  create_sweep();
  const json l = lease();
  const std::string path = "/api/v1/jobs/" + std::to_string(l["job_id"].get<int>()) + "/complete";
  const std::string b = "----b";
  const std::string body = "--" + b + "\r\nContent-Disposition: form-data; name=\"lease_token\"\r\n\r\n" +
                           l["lease_token"].get<std::string>() + "\r\n--" + b + "--";
  const std::string before = store->reads.fingerprint();
  auto r = client->Post(path.c_str(), auth(worker), body, ("multipart/form-data; boundary=" + b).c_str());
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 400);
  const json error = json::parse(r->body)["error"];
  EXPECT_EQ(error["field"], "body");
  EXPECT_NE(error["message"].get<std::string>().find("not followed by CRLF"), std::string::npos) << r->body;
  EXPECT_EQ(store->reads.fingerprint(), before);
}

TEST_F(ApiTest, ALeaseCycleOverHttpStoresTheResultOnceAndRefusesTheStaleToken) {
  const std::int64_t sweep = create_sweep();
  const json l = lease();
  const std::int64_t id = l["job_id"];
  const std::string path = "/api/v1/jobs/" + std::to_string(id);
  auto hb = post(path + "/heartbeat", json{{"lease_token", l["lease_token"]}, {"eps", 0.01}}.dump(), worker);
  EXPECT_EQ(hb->status, 200);

  // The engine's summary for exactly the leased scene.
  compaction::SceneParams p;
  ASSERT_TRUE(compaction::from_json(l["scene"], p).empty());
  compaction::RunResult run;
  run.eps_reached = 0.05;
  json summary = compaction::summary_json(p, run);
  summary["classification"] = {{"class", "c"}, {"confidence", 0.7}, {"runner_up", "b"},
                               {"n_reflections", 0}, {"band_speed_ratio", 1.6}, {"features", json::object()}};
  httplib::MultipartFormDataItems items = {
      {"lease_token", l["lease_token"], "", "text/plain"},
      {"summary", summary.dump(), "summary.json", "application/json"},
      {"files", "eps,sigma_top\n0.002,1\n", "frames.csv", "text/csv"},
  };
  auto wrong = items;
  wrong[0].content = "stale";
  const std::string before = store->reads.fingerprint();
  auto stale = client->Post((path + "/complete").c_str(), auth(worker), wrong);
  EXPECT_EQ(stale->status, 409) << stale->body;
  EXPECT_EQ(store->reads.fingerprint(), before);

  auto done = client->Post((path + "/complete").c_str(), auth(worker), items);
  ASSERT_EQ(done->status, 200) << done->body;
  auto again = client->Post((path + "/complete").c_str(), auth(worker), items);
  EXPECT_EQ(again->status, 409) << "a result is never overwritten";

  const json job = json::parse(client->Get(path.c_str())->body);
  EXPECT_EQ(job["state"], "succeeded");
  EXPECT_EQ(job["result"]["class"], "c");
  EXPECT_EQ(job["result"]["source_revision"], compaction::source_revision());
  const json map = json::parse(client->Get("/api/v1/phase-map?phi=0.4")->body);
  ASSERT_EQ(map["points"].size(), 1u);
  EXPECT_EQ(map["points"][0]["class"], "c");
  EXPECT_EQ(map["points"][0]["job_id"], id);
  // The one label predicts its class around it, and only near it.
  const json regions = json::parse(client->Get("/api/v1/phase-map/regions?phi=0.4&grid=16")->body);
  EXPECT_EQ(regions["runs"], 1);
  ASSERT_EQ(regions["classes"].size(), 16u);
  EXPECT_EQ(regions["classes"][8].get<std::string>()[8], 'c');
  EXPECT_EQ(json::parse(client->Get("/api/v1/phase-map/regions?phi=0.4&cells_per_unit=7")->body)["runs"], 0);
  // A sweep's cost before it is created, with the worker of this test connected.
  const auto estimate = client->Post("/api/v1/sweeps/estimate", R"({"name": "x", "S": [0.01, 0.02], "R": 0.001, "phi": 0.4})", "application/json");
  ASSERT_EQ(estimate->status, 200) << estimate->body;
  const json e = json::parse(estimate->body);
  EXPECT_EQ(e["jobs"], 2);
  EXPECT_GT(e["cpu_seconds"].get<double>(), 0);
  EXPECT_EQ(e["workers"], 1);
  EXPECT_DOUBLE_EQ(e["finish_seconds"].get<double>(), e["cpu_seconds"].get<double>());
  const auto artifact = client->Get((path + "/artifacts/frames.csv").c_str());
  EXPECT_EQ(artifact->body, "eps,sigma_top\n0.002,1\n");
  // An artifact is data: no browser may guess another type for it.
  EXPECT_EQ(artifact->get_header_value("X-Content-Type-Options"), "nosniff");
  const auto csv = client->Get(("/api/v1/sweeps/" + std::to_string(sweep) + "/export?format=csv").c_str());
  EXPECT_EQ(csv->status, 200);
  EXPECT_NE(csv->body.find(",c,0.7,b,"), std::string::npos) << csv->body;
  const auto metrics = client->Get("/metrics")->body;
  EXPECT_NE(metrics.find("compaction_jobs{state=\"succeeded\"} 1"), std::string::npos) << metrics;
}

TEST_F(ApiTest, RefusesFromTheHeadersAForeignOriginAWrongContentTypeAndAnOversizedBody) {
  const std::string body = R"({"name": "x", "points": [{"S": 0.05, "R": 0.001, "phi": 0.4}]})";
  const std::string before = store->reads.fingerprint();
  auto foreign = client->Post("/api/v1/sweeps",
                              {{"Authorization", "Bearer " + submit}, {"Origin", "http://evil.example"}},
                              body, "application/json");
  EXPECT_EQ(foreign->status, 403);
  EXPECT_EQ(json::parse(foreign->body)["error"]["field"], "Origin");
  auto text = client->Post("/api/v1/sweeps", auth(submit), body, "text/plain");
  EXPECT_EQ(text->status, 415);
  EXPECT_EQ(json::parse(text->body)["error"]["field"], "Content-Type");
  auto big = client->Post("/api/v1/sweeps", auth(submit), std::string(2 << 20, ' '), "application/json");
  ASSERT_TRUE(big);
  EXPECT_EQ(big->status, 413);
  EXPECT_EQ(json::parse(big->body)["error"]["field"], "body");
  EXPECT_EQ(store->reads.fingerprint(), before);
  // The server answers the next request on a new connection as usual.
  EXPECT_EQ(client->Get("/api/v1/health")->status, 200);
}

TEST_F(ApiTest, AnUploadWithABadFileOrFieldNameNamesItAndStoresNothing) {
  create_sweep();
  const json l = lease();
  const std::string path = "/api/v1/jobs/" + std::to_string(l["job_id"].get<int>()) + "/complete";
  const std::string before = store->reads.fingerprint();
  compaction::SceneParams p;
  ASSERT_TRUE(compaction::from_json(l["scene"], p).empty());
  const json summary = compaction::summary_json(p, compaction::RunResult{});
  httplib::MultipartFormDataItems items = {{"lease_token", l["lease_token"], "", "text/plain"},
                                           {"summary", summary.dump(), "summary.json", "application/json"},
                                           {"files", "x", "\xff\xfe.csv", "text/csv"}};
  auto r = client->Post(path.c_str(), auth(worker), items);
  EXPECT_EQ(r->status, 422) << r->body;
  const json e = json::parse(r->body)["error"];
  EXPECT_EQ(e["field"].get<std::string>().rfind("files[", 0), 0u) << r->body;
  items[2].name = "fi\xff";
  auto field = client->Post(path.c_str(), auth(worker), items);
  EXPECT_EQ(field->status, 422) << field->body;
  EXPECT_EQ(json::parse(field->body)["error"]["field"].get<std::string>().rfind("form[", 0), 0u);
  EXPECT_EQ(store->reads.fingerprint(), before);
}

TEST_F(ApiTest, ACompleteThatAsksForTheNextJobAnswersItsLeaseOrNull) {
  post("/api/v1/sweeps",
       R"({"name": "two", "S": [0.05, 0.06], "R": 0.001, "phi": 0.4,
           "numerics": {"cells_per_unit": 8, "eps_end": 0.05}})",
       submit);
  const auto complete = [&](const json& l, const std::string& next_lease) {
    compaction::SceneParams p;
    EXPECT_TRUE(compaction::from_json(l["scene"], p).empty());
    const json summary = compaction::summary_json(p, compaction::RunResult{});
    const std::string path = "/api/v1/jobs/" + std::to_string(l["job_id"].get<int>()) + "/complete";
    return client->Post(path.c_str(), auth(worker),
                        {{"lease_token", l["lease_token"], "", "text/plain"},
                         {"summary", summary.dump(), "summary.json", "application/json"},
                         {"next_lease", next_lease, "", "application/json"}});
  };
  const json first = lease();
  const json ask = {{"worker", "w1"}, {"engine_version", compaction::engine_version()}};

  // A bad lease request is refused like the lease endpoint's, and the result is not stored.
  const std::string before = store->reads.fingerprint();
  for (const auto& [bad, field] : std::vector<std::pair<std::string, std::string>>{
           {"{\"worker\": ", "next_lease"},
           {R"({"worker": "w1"})", "next_lease.engine_version"},
           {R"({"worker": "w1", "engine_version": "x", "extra": 1})", "next_lease.extra"}}) {
    auto r = complete(first, bad);
    EXPECT_EQ(r->status, 422) << bad << ": " << r->body;
    EXPECT_EQ(json::parse(r->body)["error"]["field"], field) << r->body;
  }
  EXPECT_EQ(store->reads.fingerprint(), before);

  auto done = complete(first, ask.dump());
  ASSERT_EQ(done->status, 200) << done->body;
  const json next = json::parse(done->body)["next"];
  ASSERT_TRUE(next.is_object()) << done->body;
  EXPECT_NE(next["job_id"], first["job_id"]);
  for (const char* key : {"lease_token", "lease_deadline", "lease_seconds", "attempt",
                          "max_attempts", "scene", "checkpoint"}) {
    EXPECT_TRUE(next.contains(key)) << key << " missing from " << next;
  }
  const json job = json::parse(client->Get(("/api/v1/jobs/" + std::to_string(next["job_id"].get<int>())).c_str())->body);
  EXPECT_EQ(job["state"], "running");
  // The queue is empty: the next complete answers "next": null.
  auto last = complete(next, ask.dump());
  ASSERT_EQ(last->status, 200) << last->body;
  EXPECT_TRUE(json::parse(last->body)["next"].is_null()) << last->body;
}

// The last queued job's result lets an adaptive sweep plan new points: the complete that asks
// for the next job gets one of them, planned after its own transaction found the queue empty.
TEST_F(ApiTest, ACompleteThatDrainsTheQueueGetsAPointItsResultPlanned) {
  auto created = post("/api/v1/sweeps",
                      R"({"name": "map", "phi": 0.4, "numerics": {"cells_per_unit": 8, "eps_end": 0.05},
                          "adaptive": {"S": {"min": 0.01, "max": 0.1}, "R": {"min": 1e-5, "max": 1e-1},
                                       "initial": {"S": 2, "R": 2}, "resolution_decades": 0.5,
                                       "budget": 10, "in_flight": 1}})",
                      submit);
  ASSERT_EQ(created->status, 201) << created->body;
  const json ask = {{"worker", "w1"}, {"engine_version", compaction::engine_version()}};
  std::vector<json> leases;
  for (int i = 0; i < 4; ++i) leases.push_back(lease());
  EXPECT_EQ(post("/api/v1/leases", ask.dump(), worker)->status, 204) << "the initial grid is leased";
  json next;
  for (const json& l : leases) {  // labels differ across R = 1e-3: the planner splits the box
    compaction::SceneParams p;
    ASSERT_TRUE(compaction::from_json(l["scene"], p).empty());
    json summary = compaction::summary_json(p, compaction::RunResult{});
    summary["classification"] = {{"class", p.R < 1e-3 ? "a" : "b"}, {"confidence", 0.9}};
    const std::string path = "/api/v1/jobs/" + std::to_string(l["job_id"].get<int>()) + "/complete";
    auto r = client->Post(path.c_str(), auth(worker),
                          {{"lease_token", l["lease_token"], "", "text/plain"},
                           {"summary", summary.dump(), "summary.json", "application/json"},
                           {"next_lease", ask.dump(), "", "application/json"}});
    ASSERT_EQ(r->status, 200) << r->body;
    next = json::parse(r->body)["next"];
    if (&l != &leases.back()) {
      EXPECT_TRUE(next.is_null()) << "nothing was queued: " << r->body;
    }
  }
  ASSERT_TRUE(next.is_object()) << "the last result planned a point and its upload leased it";
  EXPECT_GT(next["job_id"].get<int>(), leases.back()["job_id"].get<int>());
}

TEST_F(ApiTest, AnInternalErrorSaysNothingButAnIdThatIsInTheLog) {
  // A handler that fails the way a store call does, with SQL in the message.
  httplib::Server bare;
  add_route(bare, endpoints::health, [](const httplib::Request&, httplib::Response&) {
    throw std::runtime_error("SQL logic error: CHECK constraint failed: length(name) BETWEEN 1 AND 200");
  });
  const int port = bare.bind_to_any_port("127.0.0.1");
  std::thread t([&] { bare.listen_after_bind(); });
  while (!bare.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  httplib::Client c("127.0.0.1", port);
  auto r = c.Get("/api/v1/health");
  bare.stop();
  t.join();
  ASSERT_TRUE(r);
  EXPECT_EQ(r->status, 500);
  const json e = json::parse(r->body)["error"];
  EXPECT_EQ(e["message"], "internal error");
  EXPECT_FALSE(e["id"].get<std::string>().empty());
  EXPECT_EQ(r->body.find("CHECK"), std::string::npos) << r->body;
}

TEST_F(ApiTest, AnEmptyQueueAnswers204) {
  auto r = post("/api/v1/leases",
                json{{"worker", "w1"}, {"engine_version", compaction::engine_version()}}.dump(), worker);
  EXPECT_EQ(r->status, 204);
}

TEST_F(ApiTest, PolledListsAnswer304ToTheirETagUntilTheDatabaseChanges) {
  create_sweep();
  for (const char* path : {"/api/v1/phase-map?phi=0.4", "/api/v1/sweeps", "/api/v1/jobs?limit=5"}) {
    auto first = client->Get(path);
    ASSERT_EQ(first->status, 200) << path;
    const std::string tag = first->get_header_value("ETag");
    ASSERT_FALSE(tag.empty()) << path;
    EXPECT_EQ(first->get_header_value("Cache-Control"), "no-cache");
    // Its own tag, alone, weak or in a list: nothing changed, nothing sent.
    for (const std::string& inm : {tag, "W/" + tag, "\"other\", " + tag, std::string("*")}) {
      auto again = client->Get(path, {{"If-None-Match", inm}});
      EXPECT_EQ(again->status, 304) << path << " with " << inm;
      EXPECT_TRUE(again->body.empty()) << path;
      EXPECT_EQ(again->get_header_value("ETag"), tag) << path;
    }
    auto other = client->Get(path, {{"If-None-Match", "\"other\""}});
    EXPECT_EQ(other->status, 200) << path;
    EXPECT_EQ(other->body, first->body) << path;
  }
  // Another URL has another tag at the same version.
  EXPECT_NE(client->Get("/api/v1/jobs?limit=5")->get_header_value("ETag"),
            client->Get("/api/v1/jobs?limit=6")->get_header_value("ETag"));

  const std::string map = "/api/v1/phase-map?phi=0.4";
  auto before = client->Get(map.c_str());
  lease();  // a write: the job is running now
  auto after = client->Get(map.c_str(), {{"If-None-Match", before->get_header_value("ETag")}});
  ASSERT_EQ(after->status, 200);
  EXPECT_NE(after->get_header_value("ETag"), before->get_header_value("ETag"));
  EXPECT_EQ(json::parse(before->body)["points"][0]["state"], "queued");
  EXPECT_EQ(json::parse(after->body)["points"][0]["state"], "running");
}
