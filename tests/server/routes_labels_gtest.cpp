// The human-label and import endpoints in process on a loopback port: each bad input gets its
// status and the field it is about and changes nothing in the database; a label set with the
// submit token shows on the job, the phase map, its predicted regions, both exports and the
// audit, and its clear too; a file posted to /api/v1/imports merges, a bad one is refused naming
// its field.
#include <gtest/gtest.h>

#include <thread>

#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "compaction/result.hpp"
#include "exchange/export_format.hpp"
#include "loopback_api.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

const std::string named = "ana-has-her-own-token";

struct LabelApi : LoopbackApi {
  std::int64_t sweep = 0, done = 0, queued = 0;

  void configure_options(ServerOptions& o) override {
    o.tokens.add({TokenKind::submit, "ana", named}, true);  // as --tokens FILE gives them
  }
  void SetUp() override {
    LoopbackApi::SetUp();
    auto s = send("POST", "/api/v1/sweeps",
                  R"({"name": "demo", "points": [{"S": 0.05, "R": 0.001, "phi": 0.4},
                      {"S": 0.06, "R": 0.001, "phi": 0.4}],
                      "numerics": {"cells_per_unit": 6, "eps_end": 0.02}})", submit);
    ASSERT_EQ(s->status, 201) << s->body;
    sweep = json::parse(s->body)["id"];
    complete_one("a");
    queued = done == 1 ? 2 : 1;
  }
  httplib::Result send(const std::string& method, const std::string& path, const std::string& body,
                       const std::string& token) {
    httplib::Headers h;
    if (!token.empty()) h.emplace("Authorization", "Bearer " + token);
    if (method == "PUT") return client->Put(path.c_str(), h, body, "application/json");
    if (method == "DELETE") return client->Delete(path.c_str(), h, body, "application/json");
    return client->Post(path.c_str(), h, body, "application/json");
  }
  json get(const std::string& path) {
    auto r = client->Get(path.c_str());
    EXPECT_EQ(r->status, 200) << path << " " << r->body;
    return json::parse(r->body);
  }
  // Leases a job and uploads the engine's summary of its scene, labelled cls.
  void complete_one(const std::string& cls) {
    auto l = send("POST", "/api/v1/leases",
                  json{{"worker", "w1"}, {"engine_version", compaction::engine_version()}}.dump(), worker);
    ASSERT_EQ(l->status, 200);
    const json lease = json::parse(l->body);
    compaction::SceneParams p;
    ASSERT_TRUE(compaction::from_json(lease["scene"], p).empty());
    json summary = compaction::summary_json(p, compaction::RunResult{});
    summary["classification"] = {{"class", cls}, {"confidence", 0.7}, {"runner_up", "b"}};
    httplib::MultipartFormDataItems items = {
        {"lease_token", lease["lease_token"], "", "text/plain"},
        {"summary", summary.dump(), "summary.json", "application/json"},
        {"files", "eps,sigma_top\n0.002,1\n", "frames.csv", "text/csv"}};
    done = lease["job_id"];
    const std::string path = "/api/v1/jobs/" + std::to_string(done) + "/complete";
    ASSERT_EQ(client->Post(path.c_str(), {{"Authorization", "Bearer " + worker}}, items)->status, 200);
  }
  std::string label_path(std::int64_t id) { return "/api/v1/jobs/" + std::to_string(id) + "/label"; }
};

struct Bad {
  const char* what;
  const char* method;
  bool done_job;  // the job with a result, else the queued one
  std::string body;
  std::string token;
  int status;
  const char* field;
};

}  // namespace

TEST_F(LabelApi, EveryBadLabelRequestIsRefusedNamingItsFieldAndChangesNothing) {
  const json ok = {{"label", "b"}, {"reason", "reflects twice"}, {"by", "ana"}};
  auto with = [&](const char* key, json v) {
    json b = ok;
    if (v.is_null()) {
      b.erase(key);
    } else {
      b[key] = v;
    }
    return b.dump();
  };
  const std::vector<Bad> cases = {
      {"no token", "PUT", true, ok.dump(), "", 401, "Authorization"},
      {"wrong token", "PUT", true, ok.dump(), "nope", 403, "Authorization"},
      {"worker token", "PUT", true, ok.dump(), worker, 403, "Authorization"},
      {"malformed JSON", "PUT", true, "{", submit, 400, "body"},
      {"not an object", "PUT", true, "[]", submit, 422, "body"},
      {"no label", "PUT", true, with("label", nullptr), submit, 422, "label"},
      {"class g", "PUT", true, with("label", "g"), submit, 422, "label"},
      {"class as number", "PUT", true, with("label", 1), submit, 422, "label"},
      {"two letters", "PUT", true, with("label", "ab"), submit, 422, "label"},
      {"no reason", "PUT", true, with("reason", nullptr), submit, 422, "reason"},
      {"empty reason", "PUT", true, with("reason", ""), submit, 422, "reason"},
      {"reason too long", "PUT", true, with("reason", std::string(2001, 'x')), submit, 422, "reason"},
      {"reason with NUL", "PUT", true, with("reason", std::string("a\0b", 3)), submit, 422, "reason"},
      {"reason with ESC", "PUT", true, with("reason", "a\x1b[2Jb"), submit, 422, "reason"},
      {"no by", "PUT", true, with("by", nullptr), submit, 422, "by"},
      {"by with a newline", "PUT", true, with("by", "a\nb"), submit, 422, "by"},
      {"by too long", "PUT", true, with("by", std::string(201, 'x')), submit, 422, "by"},
      {"unknown key", "PUT", true, with("confidence", 1), submit, 422, "confidence"},
      {"job without result", "PUT", false, ok.dump(), submit, 409, "id"},
      {"clear without token", "DELETE", true, R"({"by": "ana"})", "", 401, "Authorization"},
      {"clear without by", "DELETE", true, R"({"reason": "x"})", submit, 422, "by"},
      {"clear unlabelled", "DELETE", true, R"({"by": "ana"})", submit, 404, "label"},
      {"clear with a label key", "DELETE", true, R"({"by": "ana", "label": "a"})", submit, 422, "label"},
      {"clear with NUL in the reason", "DELETE", true, R"({"by": "ana", "reason": "\u0000"})", submit, 422, "reason"},
  };
  const std::string before = store->reads.fingerprint();
  for (const Bad& c : cases) {
    auto r = send(c.method, label_path(c.done_job ? done : queued), c.body, c.token);
    ASSERT_TRUE(r) << c.what;
    EXPECT_EQ(r->status, c.status) << c.what << ": " << r->body;
    EXPECT_EQ(json::parse(r->body)["error"]["field"], c.field) << c.what;
  }
  auto unknown = send("PUT", label_path(999), ok.dump(), submit);
  EXPECT_EQ(unknown->status, 404);
  EXPECT_EQ(store->reads.fingerprint(), before);
  EXPECT_EQ(get("/api/v1/labels/audit")["total"], 0) << "no refused request reached the audit";
  EXPECT_EQ(client->Get("/api/v1/labels/audit?limit=0")->status, 422);
  EXPECT_EQ(client->Get("/api/v1/labels/audit?job=x")->status, 422);
}

TEST_F(LabelApi, ALabelShowsOnTheJobTheMapTheExportsAndTheAuditAndItsClearToo) {
  auto set = send("PUT", label_path(done),
                  json{{"label", "b"}, {"reason", "reflects, see the map"}, {"by", "ana"}}.dump(), submit);
  ASSERT_EQ(set->status, 200) << set->body;
  const json answer = json::parse(set->body);
  EXPECT_EQ(answer["human_label"]["label"], "b");
  EXPECT_EQ(answer["classifier"]["class"], "a");
  EXPECT_EQ(answer["total"], 1);

  const json job = get("/api/v1/jobs/" + std::to_string(done));
  EXPECT_EQ(job["human_label"]["by"], "ana");
  EXPECT_EQ(job["result"]["class"], "a");
  const json map = get("/api/v1/phase-map?phi=0.4");
  for (const json& p : map["points"]) {
    EXPECT_EQ(p["human_label"], p["job_id"] == done ? json("b") : json(nullptr));
  }
  const json exported = get("/api/v1/sweeps/" + std::to_string(sweep) + "/export?format=json");
  bool found = false;
  for (const json& j : exported["jobs"]) {
    if (j["id"] == done) {
      found = true;
      EXPECT_EQ(j["human_label"]["reason"], "reflects, see the map");
      EXPECT_EQ(j["result"]["class"], "a");
    }
  }
  EXPECT_TRUE(found);
  const std::string csv =
      client->Get(("/api/v1/sweeps/" + std::to_string(sweep) + "/export?format=csv").c_str())->body;
  EXPECT_NE(csv.find(",class,"), std::string::npos);
  EXPECT_NE(csv.find(",human_label,human_reason,human_by,human_at,"), std::string::npos);
  EXPECT_NE(csv.find(",b,\"reflects, see the map\",ana,"), std::string::npos) << csv;

  // Text a spreadsheet would run as a formula comes out as text (OWASP's CSV injection advice).
  auto formula = send("PUT", label_path(done),
                      json{{"label", "b"}, {"reason", "=HYPERLINK(\"http://evil.example\")"}, {"by", "@SUM(1+1)"}}.dump(),
                      submit);
  ASSERT_EQ(formula->status, 200) << formula->body;
  const std::string escaped =
      client->Get(("/api/v1/sweeps/" + std::to_string(sweep) + "/export?format=csv").c_str())->body;
  EXPECT_NE(escaped.find(",b,\"'=HYPERLINK(\"\"http://evil.example\"\")\",\"'@SUM(1+1)\","), std::string::npos)
      << escaped;
  EXPECT_EQ(escaped.find(",=HYPERLINK"), std::string::npos);
  EXPECT_EQ(escaped.find(",@SUM"), std::string::npos);

  auto clear = send("DELETE", label_path(done), R"({"by": "ben", "reason": "back to the classifier"})", submit);
  ASSERT_EQ(clear->status, 200) << clear->body;
  EXPECT_TRUE(json::parse(clear->body)["human_label"].is_null());
  const json audit = get("/api/v1/labels/audit");
  ASSERT_EQ(audit["total"], 3);
  EXPECT_EQ(audit["changes"][0]["action"], "cleared");
  EXPECT_EQ(audit["changes"][0]["token"], "submit") << "the token class of the request that cleared it";
  EXPECT_EQ(audit["changes"][0]["by"], "ben");
  EXPECT_EQ(audit["changes"][0]["previous_label"], "b");
  EXPECT_EQ(audit["changes"][1]["action"], "set");
  EXPECT_EQ(audit["changes"][1]["classifier_label"], "a");
  EXPECT_EQ(get("/api/v1/labels/audit?job=" + std::to_string(queued))["total"], 0);
  EXPECT_EQ(get(label_path(done))["changes"].size(), 3u);
}

TEST_F(LabelApi, APersonsLabelColoursThePredictedRegionsAsTheMapAndThePlannerReadIt) {
  // One labelled run: every cell it reaches predicts its label, the classifier's (a) before a
  // person labels it, the person's (b) after, and the classifier's again once cleared.
  auto classes = [&] {
    const json r = get("/api/v1/phase-map/regions?phi=0.4&grid=8");
    EXPECT_EQ(r["runs"], 1);
    std::string letters;
    for (const json& row : r["classes"]) letters += row.get<std::string>();
    return letters;
  };
  const std::string before = classes();
  ASSERT_NE(before.find('a'), std::string::npos) << before;
  EXPECT_EQ(before.find('b'), std::string::npos) << before;
  ASSERT_EQ(send("PUT", label_path(done),
                 json{{"label", "b"}, {"reason", "reflects"}, {"by", "ana"}}.dump(), submit)->status, 200);
  const std::string labelled = classes();
  EXPECT_EQ(labelled.find('a'), std::string::npos) << labelled;
  EXPECT_NE(labelled.find('b'), std::string::npos) << labelled;
  ASSERT_EQ(send("DELETE", label_path(done), R"({"by": "ana"})", submit)->status, 200);
  EXPECT_EQ(classes(), before);
}

TEST_F(LabelApi, AnExportPostedToImportsMergesAndABadOneIsRefusedNamingItsField) {
  const std::string file =
      client->Get(("/api/v1/sweeps/" + std::to_string(sweep) + "/export?format=archive").c_str())->body;
  ASSERT_EQ(json::parse(file)["runs"].size(), 1u);
  TempDir other_dir;
  StoreConfig c;
  c.engine_version = compaction::engine_version();
  Store other(other_dir.file("other.db"), c);
  const ExportFile f = read_export(file);
  EXPECT_EQ(other.imports.merge(f, 1).added, 1);
  const std::string other_file = *export_sweep(other, 1, "elsewhere", 2);

  const std::string before = store->reads.fingerprint();
  EXPECT_EQ(send("POST", "/api/v1/imports", other_file, "")->status, 401);
  auto cut = send("POST", "/api/v1/imports", other_file.substr(0, other_file.size() - 2), submit);
  EXPECT_EQ(cut->status, 422);
  EXPECT_EQ(json::parse(cut->body)["error"]["field"], "file");
  EXPECT_EQ(store->reads.fingerprint(), before);
  // The same runs come back from the other server: recognised, the sweep imported as such.
  auto back = send("POST", "/api/v1/imports", other_file, submit);
  ASSERT_EQ(back->status, 200) << back->body;
  const json o = json::parse(back->body);
  EXPECT_EQ(o["identical"], 1);
  EXPECT_EQ(o["added"], 0);
  EXPECT_EQ(o["sweep_created"], false) << "the sweep was made here";
  EXPECT_EQ(get("/api/v1/phase-map?phi=0.4")["points"].size(), 2u);
}

TEST_F(LabelApi, AChangeRecordsTheNameOfTheTokenThatMadeIt) {
  ASSERT_EQ(send("PUT", label_path(done), json{{"label", "b"}, {"reason", "r"}, {"by", "someone else"}}.dump(),
                 named)->status, 200);
  const json audit = get("/api/v1/labels/audit");
  EXPECT_EQ(audit["changes"][0]["by"], "someone else") << "what the person says";
  EXPECT_EQ(audit["changes"][0]["token"], "submit:ana") << "what the token proves";
  EXPECT_EQ(get("/api/v1/jobs/" + std::to_string(done))["human_label"]["token"], "submit:ana");
}
