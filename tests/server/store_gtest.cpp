// The store: leases, heartbeats, expiry, completion with live tokens only, retries,
// release, cancellation, reuse of identical parameters, the schema's state machine; the reads
// as the API shows them (views.hpp).
#include "store/store.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <set>

#include "compaction/result.hpp"
#include "plan/map_points.hpp"
#include "plan/planner.hpp"
#include "store/migrations.hpp"
#include "store/sqlite.hpp"
#include "temp_dir.hpp"
#include "views/run_table_views.hpp"
#include "views/views.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

constexpr Millis t0 = 1'000'000;  // the tests' clock starts here
constexpr Millis lease_ms = 10'000;

StoreConfig config() {
  StoreConfig c;
  c.lease_ms = lease_ms;
  c.backoff_base_ms = 1'000;
  c.engine_version = "test-1";
  return c;
}

NewSweep plan(const json& body) { return sweep_rows(plan_sweep(body), "test-1"); }

// The reads as the REST API answers them.
std::optional<json> job_of(Store& s, std::int64_t id) {
  const auto d = s.reads.job(id);
  return d ? std::optional<json>(views::job_detail(*d)) : std::nullopt;
}
std::optional<json> sweep_of(Store& s, std::int64_t id) {
  const auto r = s.reads.sweep(id);
  return r ? std::optional<json>(views::sweep(*r)) : std::nullopt;
}
json jobs_of(Store& s, const RunQuery& q) {
  const RunPage<JobRecord> page = s.reads.jobs(q);
  return views::jobs(page.items, {page.total, q.limit, q.offset, "id", std::nullopt});
}
json phase_map_of(Store& s, double phi, std::optional<std::int64_t> sweep) {
  return json::parse(views::phase_map(phi, s.reads.phase_map(phi, sweep)));
}
std::optional<json> cancel_of(Store& s, std::int64_t id, Millis now) {
  const auto n = s.sweeps.cancel(id, now);
  return n ? std::optional<json>(views::cancelled_sweep(id, *n)) : std::nullopt;
}

json points(std::initializer_list<double> S_values, int priority = 0) {
  json body = {{"name", "t"}, {"points", json::array()}, {"priority", priority},
               {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}};
  for (double S : S_values) body["points"].push_back({{"S", S}, {"R", 1e-3}, {"phi", 0.4}});
  return body;
}

ResultRecord result_for(Store& store, std::int64_t job_id, const std::string& status = "ok") {
  ResultRecord r;
  r.status = status;
  r.reason = status == "ok" ? "" : "energy blew up";
  r.scene = store.queue.job_scene(job_id)->first;
  r.engine_version = "test-1";
  r.source_revision = "abc";
  r.cls = "a";
  r.confidence = 0.9;
  r.summary = "{}";
  r.artifacts.push_back({"frames.csv", "text/csv", "eps\n0.01\n", std::nullopt});
  return r;
}

struct StoreTest : ::testing::Test {
  TempDir dir;
  Store store{dir.file("jobs.db"), config()};
};

}  // namespace

TEST_F(StoreTest, LeaseTakesTheHighestPriorityThenTheOldestJob) {
  store.sweeps.create(plan(points({0.01, 0.02})), t0);
  store.sweeps.create(plan(points({0.03}, 5)), t0);
  auto a = store.queue.lease("w", "test-1", t0);
  ASSERT_TRUE(a);
  EXPECT_EQ(json::parse(a->scene)["S"], 0.03);
  auto b = store.queue.lease("w", "test-1", t0);
  EXPECT_EQ(json::parse(b->scene)["S"], 0.01);
  EXPECT_NE(a->token, b->token);
  EXPECT_EQ(a->deadline, t0 + lease_ms);
  auto c = store.queue.lease("w", "test-1", t0);
  ASSERT_TRUE(c);
  EXPECT_FALSE(store.queue.lease("w", "test-1", t0)) << "the queue is empty";
}

TEST_F(StoreTest, LeaseOnlyHandsOutJobsOfTheWorkersEngineVersion) {
  store.sweeps.create(plan(points({0.01})), t0);
  EXPECT_FALSE(store.queue.lease("w", "other-version", t0));
  EXPECT_TRUE(store.queue.lease("w", "test-1", t0));
}

TEST_F(StoreTest, HeartbeatExtendsTheLeaseAndRecordsProgress) {
  store.sweeps.create(plan(points({0.01})), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  Millis deadline = 0;
  EXPECT_EQ(store.queue.heartbeat(l->job_id, l->token, 0.01, t0 + 5'000, deadline), LeaseCheck::ok);
  EXPECT_EQ(deadline, t0 + 5'000 + lease_ms);
  EXPECT_EQ(store.queue.requeue_expired(t0 + lease_ms + 1), 0) << "the heartbeat moved the deadline";
  EXPECT_DOUBLE_EQ((*job_of(store, l->job_id))["progress_eps"].get<double>(), 0.01);
  EXPECT_EQ(store.queue.heartbeat(l->job_id, "not-the-token", 0.01, t0, deadline), LeaseCheck::lost);
  EXPECT_EQ(store.queue.heartbeat(999, l->token, 0.01, t0, deadline), LeaseCheck::unknown_job);
}

TEST_F(StoreTest, AnExpiredLeaseReturnsTheJobAndTheStaleTokenCanNeverComplete) {
  store.sweeps.create(plan(points({0.01})), t0);
  auto first = store.queue.lease("dead-worker", "test-1", t0);
  EXPECT_EQ(store.queue.requeue_expired(t0 + lease_ms), 0) << "not expired at the deadline itself";
  EXPECT_EQ(store.queue.requeue_expired(t0 + lease_ms + 1), 1);
  EXPECT_EQ((*job_of(store, first->job_id))["state"], "queued");

  auto second = store.queue.lease("live-worker", "test-1", t0 + lease_ms + 2);
  ASSERT_TRUE(second);
  EXPECT_EQ(second->job_id, first->job_id);
  EXPECT_EQ(second->attempt, 2);
  const std::string before = store.reads.fingerprint();
  EXPECT_EQ(store.queue.complete(first->job_id, first->token, result_for(store, first->job_id), t0),
            LeaseCheck::lost);
  Millis deadline = 0;
  EXPECT_EQ(store.queue.heartbeat(first->job_id, first->token, 0.0, t0, deadline), LeaseCheck::lost);
  EXPECT_EQ(store.queue.fail(first->job_id, first->token, "x", true, t0).check, LeaseCheck::lost);
  EXPECT_EQ(store.queue.release(first->job_id, first->token, t0), LeaseCheck::lost);
  EXPECT_EQ(store.reads.fingerprint(), before) << "a stale token changes nothing";

  EXPECT_EQ(store.queue.complete(second->job_id, second->token, result_for(store, second->job_id),
                           t0 + lease_ms + 3),
            LeaseCheck::ok);
  const json job = *job_of(store, first->job_id);
  EXPECT_EQ(job["state"], "succeeded");
  EXPECT_EQ(job["result"]["worker"], "live-worker");
  EXPECT_EQ(job["result"]["engine_version"], "test-1");
  EXPECT_EQ(job["result"]["source_revision"], "abc");
  // Completing twice, even with the token that won, is refused: results are never overwritten.
  EXPECT_EQ(store.queue.complete(second->job_id, second->token, result_for(store, second->job_id), t0),
            LeaseCheck::lost);
  const auto m = store.reads.metrics();
  EXPECT_EQ(m.events_by_kind.size() > 0, true);
}

TEST_F(StoreTest, ACompleteThatAsksForTheNextJobLeasesItInTheSameCommit) {
  store.sweeps.create(plan(points({0.01, 0.02})), t0);
  const auto first = store.queue.lease("w", "test-1", t0);
  QueueStore::FollowUps follow;
  ASSERT_EQ(store.queue.complete(first->job_id, first->token, result_for(store, first->job_id),
                                 t0 + 5, QueueStore::LeaseRequest{"w", "test-1"}, &follow),
            LeaseCheck::ok);
  EXPECT_FALSE(follow.checkpoint);
  EXPECT_TRUE(follow.adaptive_sweeps.empty()) << "a list sweep is not adaptive";
  const std::optional<Lease>& next = follow.next;
  ASSERT_TRUE(next);
  EXPECT_NE(next->job_id, first->job_id);
  EXPECT_EQ(next->deadline, t0 + 5 + lease_ms);
  EXPECT_EQ(next->attempt, 1);
  const json job = *job_of(store, next->job_id);
  EXPECT_EQ(job["state"], "running");
  EXPECT_EQ(job["worker"], "w");
  EXPECT_EQ((*job_of(store, first->job_id))["state"], "succeeded");
  // The queue is empty now: the next complete succeeds and leases nothing.
  QueueStore::FollowUps last;
  last.next = Lease{};
  ASSERT_EQ(store.queue.complete(next->job_id, next->token, result_for(store, next->job_id), t0 + 6,
                                 QueueStore::LeaseRequest{"w", "test-1"}, &last),
            LeaseCheck::ok);
  EXPECT_FALSE(last.next);
}

TEST_F(StoreTest, ACompleteWithALostLeaseLeasesNothing) {
  store.sweeps.create(plan(points({0.01, 0.02})), t0);
  const auto first = store.queue.lease("w", "test-1", t0);
  const std::string before = store.reads.fingerprint();
  QueueStore::FollowUps follow;
  EXPECT_EQ(store.queue.complete(first->job_id, "stale", result_for(store, first->job_id), t0,
                                 QueueStore::LeaseRequest{"w", "test-1"}, &follow),
            LeaseCheck::lost);
  EXPECT_FALSE(follow.next);
  EXPECT_EQ(store.reads.fingerprint(), before) << "the other job is still queued";
}

TEST_F(StoreTest, ALeaseExpiringOnTheLastAttemptFailsTheJob) {
  json body = points({0.01});
  body["max_attempts"] = 1;
  store.sweeps.create(plan(body), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  EXPECT_EQ(store.queue.requeue_expired(t0 + lease_ms + 1), 1);
  const json job = *job_of(store, l->job_id);
  EXPECT_EQ(job["state"], "failed");
  EXPECT_NE(job["last_error"].get<std::string>().find("lease expired"), std::string::npos);
}

TEST_F(StoreTest, RetryableFailuresRequeueWithGrowingBackoffUntilTheAttemptsAreUsed) {
  store.sweeps.create(plan(points({0.01})), t0);  // max_attempts 3
  auto l1 = store.queue.lease("w", "test-1", t0);
  auto f1 = store.queue.fail(l1->job_id, l1->token, "runner crashed: signal 11", true, t0);
  EXPECT_EQ(f1.state, JobState::queued);
  EXPECT_EQ(f1.run_after, t0 + 1'000);
  EXPECT_FALSE(store.queue.lease("w", "test-1", t0 + 999)) << "backoff not over";
  auto l2 = store.queue.lease("w", "test-1", t0 + 1'000);
  ASSERT_TRUE(l2);
  auto f2 = store.queue.fail(l2->job_id, l2->token, "again", true, t0 + 1'000);
  EXPECT_EQ(f2.run_after, t0 + 1'000 + 2'000) << "the backoff doubles";
  auto l3 = store.queue.lease("w", "test-1", t0 + 3'000);
  ASSERT_TRUE(l3);
  EXPECT_EQ(store.queue.fail(l3->job_id, l3->token, "third", true, t0 + 3'000).state, JobState::failed);
  const json job = *job_of(store, l3->job_id);
  EXPECT_EQ(job["state"], "failed");
  EXPECT_EQ(job["attempts"], 3);
  EXPECT_EQ(job["last_error"], "third");
  int retries = 0;
  for (const auto& e : job["events"]) retries += e["kind"] == "retry";
  EXPECT_EQ(retries, 2);
}

TEST_F(StoreTest, ANonRetryableFailureFailsAtOnce) {
  store.sweeps.create(plan(points({0.01})), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  EXPECT_EQ(store.queue.fail(l->job_id, l->token, "invalid input", false, t0).state, JobState::failed);
}

TEST_F(StoreTest, ReleaseRequeuesAtOnceWithoutCountingTheAttempt) {
  store.sweeps.create(plan(points({0.01})), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  EXPECT_EQ(store.queue.release(l->job_id, l->token, t0 + 10), LeaseCheck::ok);
  auto again = store.queue.lease("w2", "test-1", t0 + 10);
  ASSERT_TRUE(again);
  EXPECT_EQ(again->attempt, 1);
}

TEST_F(StoreTest, IdenticalParametersAreComputedOnceAndReusedByLaterSweeps) {
  auto s1 = store.sweeps.create(plan(points({0.01, 0.02})), t0);
  EXPECT_EQ(s1.n_new, 2);
  auto l = store.queue.lease("w", "test-1", t0);
  ASSERT_EQ(store.queue.complete(l->job_id, l->token, result_for(store, l->job_id), t0), LeaseCheck::ok);
  auto s2 = store.sweeps.create(plan(points({0.01, 0.02, 0.03})), t0);
  EXPECT_EQ(s2.n_jobs, 3);
  EXPECT_EQ(s2.n_new, 1);
  EXPECT_EQ(s2.n_reused, 1);
  EXPECT_EQ(s2.n_shared, 1);
  const json sweep = *sweep_of(store, s2.id);
  EXPECT_EQ(sweep["counts"]["succeeded"], 1);
  EXPECT_EQ(sweep["counts"]["queued"], 2);
  EXPECT_EQ(jobs_of(store, {}).at("total"), 3);
}

TEST_F(StoreTest, CancelSparesJobsThatAnotherLiveSweepWants) {
  auto a = store.sweeps.create(plan(points({0.01, 0.02})), t0);
  store.sweeps.create(plan(points({0.02})), t0);
  auto l = store.queue.lease("w", "test-1", t0);  // S = 0.01, only in sweep a
  const json out = *cancel_of(store, a.id, t0 + 1);
  EXPECT_EQ(out["cancelled_jobs"], 1);
  EXPECT_EQ((*job_of(store, l->job_id))["state"], "cancelled");
  Millis deadline = 0;
  EXPECT_EQ(store.queue.heartbeat(l->job_id, l->token, 0.0, t0 + 2, deadline), LeaseCheck::lost)
      << "the worker learns of the cancel at its next heartbeat";
  EXPECT_EQ((*sweep_of(store, a.id))["state"], "cancelled");
  EXPECT_FALSE(cancel_of(store, 12345, t0));
  // A new sweep asking for a cancelled job queues it again.
  auto c = store.sweeps.create(plan(points({0.01})), t0 + 3);
  EXPECT_EQ(c.n_requeued, 1);
  EXPECT_EQ((*job_of(store, l->job_id))["state"], "queued");
}

TEST_F(StoreTest, PhaseMapListsTheJobsAtOnePhiWithTheirLabels) {
  store.sweeps.create(plan(points({0.01, 0.02})), t0);
  json other = points({0.05});
  other["points"][0]["phi"] = 0.5;
  store.sweeps.create(plan(other), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  store.queue.complete(l->job_id, l->token, result_for(store, l->job_id), t0);
  const json map = phase_map_of(store, 0.4, std::nullopt);
  ASSERT_EQ(map["points"].size(), 2u);
  EXPECT_EQ(map["points"][0]["class"], "a");
  EXPECT_EQ(map["points"][0]["state"], "succeeded");
  EXPECT_TRUE(map["points"][1]["class"].is_null());
  EXPECT_EQ(phase_map_of(store, 0.5, std::nullopt)["points"].size(), 1u);
}

// Random structures are squares on the band-speed plot: the map names each point's structure,
// and a scene stored before the key existed is regular.
TEST_F(StoreTest, PhaseMapNamesEachPointsStructure) {
  store.sweeps.create(plan(points({0.01})), t0);
  json random = points({0.01, 0.02});
  random["numerics"]["cells_per_unit"] = 12;  // the thinnest random strut needs a grid cell
  random["numerics"]["structure"] = "random";
  random["numerics"]["seeds"] = json::parse("[1, 2]");
  store.sweeps.create(plan(random), t0);
  {
    // A scene written before the key existed has none, and migration 0008 left its column NULL.
    sqlite::Database db(dir.file("jobs.db"));
    db.prepare("UPDATE jobs SET scene = json_remove(scene, '$.structure'), structure = NULL"
               " WHERE id = 1").run();
  }
  const json map = phase_map_of(store, 0.4, std::nullopt);
  ASSERT_EQ(map["points"].size(), 5u);
  std::map<std::string, int> by_structure;
  for (const json& p : map["points"]) by_structure[p["structure"].get<std::string>()]++;
  EXPECT_EQ(by_structure, (std::map<std::string, int>{{"random", 4}, {"regular", 1}}));
}

TEST_F(StoreTest, PhaseMapCarriesBothReadingsOfTheBandSpeedWithTheirUncertainties) {
  store.sweeps.create(plan(points({0.01, 0.02, 0.03})), t0);
  const auto complete = [&](const json& features) {
    auto l = store.queue.lease("w", "test-1", t0);
    ResultRecord r = result_for(store, l->job_id);
    r.band_speed_ratio = features.value("band_speed_ratio", json()).is_number()
                             ? std::optional<double>(features["band_speed_ratio"].get<double>())
                             : std::nullopt;
    r.features = features.dump();
    store.queue.complete(l->job_id, l->token, r, t0);
  };
  complete({{"band_speed_ratio", 1.73}, {"band_speed_error", 0.008}, {"band_speed_transit", 1.694},
            {"band_speed_transit_error", 0.016}, {"band_speed_early", 2.14},
            {"band_speed_early_error", 0.009}, {"band_speed_lead", 2.79},
            {"band_speed_lead_error", 0.01}});
  complete({{"band_speed_ratio", nullptr}, {"band_speed_error", nullptr}});  // no band
  complete({{"band_speed_error", "wide"}});                                 // not a number
  const json map = phase_map_of(store, 0.4, std::nullopt);
  ASSERT_EQ(map["points"].size(), 3u);
  const json& band = map["points"][0];
  EXPECT_DOUBLE_EQ(band["band_speed_ratio"].get<double>(), 1.73);
  EXPECT_DOUBLE_EQ(band["band_speed_error"].get<double>(), 0.008);
  EXPECT_DOUBLE_EQ(band["band_speed_transit"].get<double>(), 1.694);
  EXPECT_DOUBLE_EQ(band["band_speed_transit_error"].get<double>(), 0.016);
  EXPECT_DOUBLE_EQ(band["band_speed_early"].get<double>(), 2.14);
  EXPECT_DOUBLE_EQ(band["band_speed_early_error"].get<double>(), 0.009);
  EXPECT_DOUBLE_EQ(band["band_speed_lead"].get<double>(), 2.79);
  EXPECT_DOUBLE_EQ(band["band_speed_lead_error"].get<double>(), 0.01);
  for (int i : {1, 2}) {
    for (const char* k : {"band_speed_ratio", "band_speed_error", "band_speed_transit",
                          "band_speed_transit_error", "band_speed_early", "band_speed_early_error",
                          "band_speed_lead", "band_speed_lead_error"}) {
      EXPECT_TRUE(map["points"][i][k].is_null()) << "point " << i << ", " << k;
    }
  }
}

TEST_F(StoreTest, ArtifactsAreStoredWithTheResult) {
  store.sweeps.create(plan(points({0.01})), t0);
  auto l = store.queue.lease("w", "test-1", t0);
  store.queue.complete(l->job_id, l->token, result_for(store, l->job_id, "unstable"), t0);
  const auto a = store.reads.artifact(l->job_id, "frames.csv");
  ASSERT_TRUE(a);
  EXPECT_EQ(a->data, "eps\n0.01\n");
  EXPECT_EQ((*store.reads.artifacts(l->job_id)).size(), 1u);
  EXPECT_EQ((*job_of(store, l->job_id))["result"]["status"], "unstable");
  EXPECT_EQ((*job_of(store, l->job_id))["state"], "succeeded") << "an unstable run is a result";
}

TEST(StoreSchema, MigrationsAreAppliedOnceAndRecorded) {
  TempDir dir;
  { Store s(dir.file("db"), config()); }
  { Store s(dir.file("db"), config()); }  // reopening applies nothing twice
  sqlite::Database db(dir.file("db"));
  auto q = db.prepare("SELECT count(*), min(name) FROM schema_migrations");
  ASSERT_TRUE(q.step());
  EXPECT_EQ(q.int64(0), static_cast<std::int64_t>(embedded_migrations().size()));
  EXPECT_EQ(q.text(1), "0001_init.sql");
}

// A database at dir whose results carry these features (one job each), then set back by the SQL
// `roll_back` to the schema before a migration: opened again, the migration runs on results
// written before it.
void results_before_migration(const TempDir& dir, const std::vector<json>& features,
                              const char* roll_back) {
  {
    Store s(dir.file("db"), config());
    json sweep = points({});
    for (std::size_t i = 0; i < features.size(); ++i) {
      sweep["points"].push_back({{"S", 0.01 * static_cast<double>(i + 1)}, {"R", 1e-3}, {"phi", 0.4}});
    }
    s.sweeps.create(plan(sweep), t0);
    for (const json& f : features) {
      auto l = s.queue.lease("w", "test-1", t0);
      ResultRecord r = result_for(s, l->job_id);
      r.features = f.dump();
      s.queue.complete(l->job_id, l->token, r, t0);
    }
  }
  sqlite::Database(dir.file("db")).exec_script(roll_back);
}

// Migration 0008 on a database written before it: the band-speed readings move from the
// features into their columns (numbers only), the structure from the scene, and the map reads
// the same values as the intake writes for a new result.
TEST(StoreSchema, TheMapColumnsAreFilledFromTheFeaturesAndScenesOfEarlierRuns) {
  TempDir dir;
  // Back to the schema of 0007: without the columns, the indexes and the record of 0008.
  results_before_migration(
      dir,
      {json{{"band_speed_error", 0.008}, {"band_speed_transit", 1.694},
            {"band_speed_transit_error", 2}},
       json{{"band_speed_error", "wide"}, {"band_speed_transit", nullptr}}},
      "DROP INDEX jobs_map; DROP INDEX results_map; CREATE INDEX jobs_phi ON jobs (phi);"
      "ALTER TABLE results DROP COLUMN band_speed_error;"
      "ALTER TABLE results DROP COLUMN band_speed_transit;"
      "ALTER TABLE results DROP COLUMN band_speed_transit_error;"
      "ALTER TABLE jobs DROP COLUMN structure;"
      "DELETE FROM schema_migrations WHERE name = '0008_phase_map_columns.sql';");
  Store s(dir.file("db"), config());
  const json map = phase_map_of(s, 0.4, std::nullopt);
  ASSERT_EQ(map["points"].size(), 2u);
  const json& numbers = map["points"][0];
  EXPECT_EQ(numbers["band_speed_error"], 0.008);
  EXPECT_EQ(numbers["band_speed_transit"], 1.694);
  EXPECT_EQ(numbers["band_speed_transit_error"], 2.0) << "an integer is a number";
  const json& others = map["points"][1];
  EXPECT_TRUE(others["band_speed_error"].is_null()) << "a text is not a number";
  EXPECT_TRUE(others["band_speed_transit"].is_null());
  EXPECT_TRUE(others["band_speed_transit_error"].is_null()) << "absent";
  for (const json& p : map["points"]) EXPECT_EQ(p["structure"], "regular");
}

// Migration 0009 on a database written before it: the early-stage readings move from the
// features into their columns (numbers only), as the intake writes them for a new result.
TEST(StoreSchema, TheEarlyStageColumnsAreFilledFromTheFeaturesOfEarlierRuns) {
  TempDir dir;
  // Back to the schema of 0008: without the columns and the record of 0009.
  results_before_migration(
      dir,
      {json{{"band_speed_early", 2.14}, {"band_speed_early_error", 0.009},
            {"band_speed_lead", 3}, {"band_speed_lead_error", 0.01}},
       json{{"band_speed_early", "fast"}, {"band_speed_lead", nullptr}}},
      "DROP INDEX results_map;"
      "CREATE INDEX results_map ON results (job_id, status, class, confidence, runner_up,"
      " n_reflections, band_speed_ratio, band_speed_error, band_speed_transit,"
      " band_speed_transit_error);"
      "ALTER TABLE results DROP COLUMN band_speed_early;"
      "ALTER TABLE results DROP COLUMN band_speed_early_error;"
      "ALTER TABLE results DROP COLUMN band_speed_lead;"
      "ALTER TABLE results DROP COLUMN band_speed_lead_error;"
      "DELETE FROM schema_migrations WHERE name = '0009_early_stage_columns.sql';");
  Store s(dir.file("db"), config());
  const json map = phase_map_of(s, 0.4, std::nullopt);
  ASSERT_EQ(map["points"].size(), 2u);
  const json& numbers = map["points"][0];
  EXPECT_EQ(numbers["band_speed_early"], 2.14);
  EXPECT_EQ(numbers["band_speed_early_error"], 0.009);
  EXPECT_EQ(numbers["band_speed_lead"], 3.0) << "an integer is a number";
  EXPECT_EQ(numbers["band_speed_lead_error"], 0.01);
  const json& others = map["points"][1];
  EXPECT_TRUE(others["band_speed_early"].is_null()) << "a text is not a number";
  EXPECT_TRUE(others["band_speed_early_error"].is_null()) << "absent";
  EXPECT_TRUE(others["band_speed_lead"].is_null()) << "null";
}

// Migration 0011 on a database written before it: jobs that differ only by their seed share a
// point, any other difference (S, the perturbation, the engine version) makes another.
TEST(StoreSchema, ThePointsOfEarlierJobsAreTheirScenesUpToTheSeed) {
  TempDir dir;
  {
    sqlite::Database db(dir.file("db"));
    std::vector<Migration> before;
    for (const Migration& m : embedded_migrations()) {
      if (m.version < 11) before.push_back(m);
    }
    apply_migrations(db, before);
    compaction::SceneParams p;
    p.perturbation = 0.01;
    const auto insert = [&](const compaction::SceneParams& scene, const std::string& version) {
      const NewJob row = job_row(scene, version);
      db.prepare(
            "INSERT INTO jobs (identity, scene, engine_version, S, R, phi, cells_per_unit, eps_end,"
            " run_after, created_at) VALUES (?, ?, ?, ?, ?, ?, ?, ?, 0, 0)")
          .bind(1, row.identity).bind(2, row.scene).bind(3, version).bind(4, row.S).bind(5, row.R)
          .bind(6, row.phi).bind(7, row.cells_per_unit).bind(8, row.eps_end).run();
    };
    for (std::uint64_t seed : {1, 2, 3}) {  // jobs 1-3: one point
      p.seed = seed;
      insert(p, "test-1");
    }
    compaction::SceneParams other_S = p;  // job 4
    other_S.S *= 2;
    insert(other_S, "test-1");
    compaction::SceneParams other_perturbation = p;  // job 5
    other_perturbation.perturbation = 0.02;
    insert(other_perturbation, "test-1");
    insert(p, "test-0");  // job 6: another engine version
  }
  Store s(dir.file("db"), config());
  sqlite::Database db(dir.file("db"));
  auto q = db.prepare("SELECT point_id FROM jobs ORDER BY id");
  std::vector<std::int64_t> ids;
  while (q.step()) ids.push_back(q.int64(0));
  ASSERT_EQ(ids.size(), 6u);
  EXPECT_EQ(ids[0], ids[1]);
  EXPECT_EQ(ids[0], ids[2]);
  EXPECT_EQ(std::set<std::int64_t>(ids.begin() + 2, ids.end()).size(), 4u) << "4 other points";
  EXPECT_GT(ids[0], 0);
}

// A sweep's replicates (and an import's jobs: the same trigger) find their point as they are
// inserted; the map serves the point with its runs.
TEST_F(StoreTest, ReplicatesShareTheirPointAndTheMapSummarisesThem) {
  json body = points({0.01, 0.02});
  body["replicates"] = {{"n", 3}, {"perturbation", 0.01}};
  const CreatedSweep c = store.sweeps.create(plan(body), t0);
  ASSERT_EQ(c.n_jobs, 6);
  // Two replicates of S = 0.01 finish with (a), one with (b); S = 0.02 stays queued.
  for (const char* cls : {"a", "b", "a"}) {
    auto l = store.queue.lease("w", "test-1", t0);
    ASSERT_TRUE(l);
    ResultRecord r = result_for(store, l->job_id);
    r.cls = cls;
    r.band_speed_ratio = *r.cls == "a" ? 2.0 : 5.0;
    store.queue.complete(l->job_id, l->token, r, t0);
  }
  const json map = phase_map_of(store, 0.4, c.id);
  ASSERT_EQ(map["points"].size(), 6u) << "the runs, as before";
  ASSERT_EQ(map["summaries"].size(), 2u);
  const json& done = map["summaries"][0];
  EXPECT_EQ(done["S"], 0.01);
  EXPECT_EQ(done["runs"], 3);
  EXPECT_EQ(done["finished"], 3);
  EXPECT_EQ(done["label"], "a");
  EXPECT_NEAR(done["share"].get<double>(), 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(done["probabilities"]["b"].get<double>(), 1.0 / 3.0, 1e-12);
  EXPECT_EQ(done["robust"], false);
  // c_b/V over the majority's runs: (a)'s 2.0 twice, not (b)'s 5.0
  EXPECT_EQ(done["band_speed_ratio"]["mean"], 2.0);
  EXPECT_EQ(done["band_speed_ratio"]["sd"], 0.0);
  EXPECT_EQ(done["band_speed_ratio"]["n"], 2);
  EXPECT_EQ(done["jobs"].size(), 3u);
  for (const json& run : map["points"]) {
    const bool mine = std::find(done["jobs"].begin(), done["jobs"].end(), run["job_id"]) != done["jobs"].end();
    EXPECT_EQ(run["point_id"] == done["point_id"], mine);
  }
  const json& queued = map["summaries"][1];
  EXPECT_EQ(queued["finished"], 0);
  EXPECT_TRUE(queued["label"].is_null());
  EXPECT_TRUE(queued["share"].is_null());
}

TEST(StoreSchema, AnEditedMigrationIsRefused) {
  TempDir dir;
  { Store s(dir.file("db"), config()); }
  sqlite::Database db(dir.file("db"));
  auto edited = embedded_migrations();
  edited[0].sql += "\n-- edited";
  EXPECT_THROW(apply_migrations(db, edited), std::runtime_error);
}

TEST(StoreSchema, TheSchemaRefusesUnknownStatesAndLeaselessRunningJobs) {
  TempDir dir;
  {
    Store s(dir.file("db"), config());
    s.sweeps.create(plan(points({0.01})), t0);
  }
  sqlite::Database db(dir.file("db"));
  EXPECT_THROW(db.prepare("UPDATE jobs SET state = 'done'").run(), sqlite::Error);
  EXPECT_THROW(db.prepare("UPDATE jobs SET state = 'running'").run(), sqlite::Error);
  EXPECT_THROW(db.prepare("INSERT INTO results (job_id, status, scene, engine_version,"
                          " source_revision, summary, worker, created_at)"
                          " VALUES (1, 'cancelled', '{}', 'v', 'r', '{}', 'w', 0)")
                   .run(),
               sqlite::Error);
}

TEST_F(StoreTest, TheEventLogOfAJobLeasedAndReleasedForeverStaysBoundedAndCountsWhatItDropped) {
  store.sweeps.create(plan(points({0.01})), t0);
  std::int64_t id = 0;
  for (int i = 0; i < 300; ++i) {
    const auto l = store.queue.lease("w", "test-1", t0 + i);
    ASSERT_TRUE(l);
    id = l->job_id;
    ASSERT_EQ(store.queue.release(id, l->token, t0 + i), LeaseCheck::ok);
  }
  const json j = *job_of(store, id);
  EXPECT_EQ(j["events"].size(), static_cast<std::size_t>(max_events_per_job));
  // 600 events in all (a lease and a release per cycle); the newest is the last release.
  EXPECT_EQ(j["events_dropped"].get<int>() + static_cast<int>(j["events"].size()), 600);
  EXPECT_EQ(j["events"].back()["kind"], "released");
  // The totals behind the metrics' counters count every event, dropped or not.
  const StoreMetrics m = store.reads.metrics();
  std::int64_t leased = 0, released = 0;
  for (const auto& [kind, n] : m.events_by_kind) {
    if (kind == "leased") leased = n;
    if (kind == "released") released = n;
  }
  EXPECT_EQ(leased, 300);
  EXPECT_EQ(released, 300);
}

TEST_F(StoreTest, ArtifactsAreFilesBesideTheDatabaseAndAnUploadThatLostItsLeaseLeavesNone) {
  store.sweeps.create(plan(points({0.01, 0.02})), t0);
  const auto a = store.queue.lease("w", "test-1", t0);
  ResultRecord r = result_for(store, a->job_id);
  r.artifacts.push_back({"spacetime.npy", "application/octet-stream", std::string(100000, '\x7f'), std::nullopt});
  ASSERT_EQ(store.queue.complete(a->job_id, a->token, r, t0 + 1), LeaseCheck::ok);
  const auto npy = store.reads.artifact(a->job_id, "spacetime.npy");
  ASSERT_TRUE(npy);
  EXPECT_EQ(npy->data, std::string(100000, '\x7f'));
  const std::filesystem::path root = dir.file("jobs.db.artifacts");
  ASSERT_EQ(std::distance(std::filesystem::directory_iterator(root), {}), 1);

  // A stale token: the files are written first, then removed when the transaction refuses.
  const auto b = store.queue.lease("w", "test-1", t0 + 2);
  ResultRecord stale = result_for(store, b->job_id);
  EXPECT_EQ(store.queue.complete(b->job_id, "stale", stale, t0 + 3), LeaseCheck::lost);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(root), {}), 1);
}

TEST(StoreStart, RemovesTheFilesOfAnUploadThatNeverCommittedAndKeepsTheOthers) {
  TempDir dir;
  std::int64_t job = 0;
  {
    Store store(dir.file("jobs.db"), config());
    store.sweeps.create(plan(points({0.01})), t0);
    const auto l = store.queue.lease("w", "test-1", t0);
    job = l->job_id;
    ASSERT_EQ(store.queue.complete(job, l->token, result_for(store, job), t0 + 1), LeaseCheck::ok);
  }
  // What a crash between writing the files and the commit leaves.
  const std::filesystem::path orphan = dir.path / "jobs.db.artifacts" / "job-9-deadbeef";
  std::filesystem::create_directories(orphan);
  std::ofstream(orphan / "frames.csv") << "eps\n";
  Store store(dir.file("jobs.db"), config());
  EXPECT_FALSE(std::filesystem::exists(orphan));
  EXPECT_EQ(store.reads.artifact(job, "frames.csv")->data, "eps\n0.01\n");
}

TEST_F(StoreTest, ReadsSeeTheCommittedStateWhileAnotherConnectionHoldsTheWriteLock) {
  store.sweeps.create(plan(points({0.01})), t0);
  sqlite::Database other(dir.file("jobs.db"));
  sqlite::Transaction holding(other);
  other.prepare("UPDATE jobs SET priority = 5").run();
  EXPECT_EQ(jobs_of(store, {})["jobs"][0]["priority"], 0);
  EXPECT_EQ(phase_map_of(store, 0.4, std::nullopt)["points"].size(), 1u);
  ASSERT_TRUE(sweep_of(store, 1));
  EXPECT_EQ((*sweep_of(store, 1))["counts"]["queued"], 1);
}

TEST(PhaseMapView, TheWrittenTextReadsAsWhatJsonObjectsWouldWrite) {
  // The slow way the text is written fast: an object per point, dumped.
  const auto slow = [](double phi, const std::vector<PhaseMapPoint>& points) {
    const auto opt = [](const auto& v) { return v ? json(*v) : json(nullptr); };
    json out = json::array();
    for (const PhaseMapPoint& p : points) {
      out.push_back({{"S", p.S}, {"R", p.R}, {"phi", p.phi}, {"state", p.state},
                     {"class", opt(p.cls)}, {"confidence", opt(p.confidence)},
                     {"runner_up", opt(p.runner_up)}, {"n_reflections", opt(p.n_reflections)},
                     {"band_speed_ratio", opt(p.band_speed_ratio)},
                     {"band_speed_error", opt(p.band_speed_error)},
                     {"band_speed_transit", opt(p.band_speed_transit)},
                     {"band_speed_transit_error", opt(p.band_speed_transit_error)},
                     {"band_speed_early", opt(p.band_speed_early)},
                     {"band_speed_early_error", opt(p.band_speed_early_error)},
                     {"band_speed_lead", opt(p.band_speed_lead)},
                     {"band_speed_lead_error", opt(p.band_speed_lead_error)},
                     {"job_id", p.job_id}, {"status", opt(p.status)},
                     {"cells_per_unit", p.cells_per_unit},
                     {"cells_per_strut", p.cells_per_unit * compaction::strut_fraction(p.phi)},
                     {"eps_end", p.eps_end}, {"progress_eps", opt(p.progress_eps)},
                     {"human_label", opt(p.human_label)}, {"structure", p.structure},
                     {"point_id", p.point_id}});
    }
    const auto spread_json = [](const std::optional<Spread>& s) {
      return s ? json{{"mean", s->mean}, {"n", s->n}, {"sd", s->sd ? json(*s->sd) : json(nullptr)}}
               : json(nullptr);
    };
    json summaries = json::array();
    for (const MapPoint& m : map_points(points)) {
      json probabilities = json::object();
      for (const auto& [label, share] : m.tally.probabilities) probabilities[label] = share;
      summaries.push_back(
          {{"point_id", m.point_id}, {"S", m.S}, {"R", m.R}, {"phi", m.phi}, {"eps_end", m.eps_end},
           {"cells_per_unit", m.cells_per_unit},
           {"cells_per_strut", m.cells_per_unit * compaction::strut_fraction(m.phi)},
           {"structure", m.structure}, {"jobs", m.jobs}, {"runs", m.tally.runs},
           {"finished", m.tally.finished}, {"labelled", m.tally.labelled},
           {"probabilities", probabilities}, {"label", opt(m.tally.label)},
           {"share", m.tally.label ? json(m.tally.share) : json(nullptr)},
           {"robust", m.tally.robust}, {"band_speed_ratio", spread_json(m.band_speed_ratio)},
           {"band_speed_early", spread_json(m.band_speed_early)},
           {"band_speed_lead", spread_json(m.band_speed_lead)},
           {"band_speed_transit", spread_json(m.band_speed_transit)},
           {"n_reflections", spread_json(m.n_reflections)}});
    }
    return json{{"model", views::model(phi)}, {"phi", phi}, {"points", out}, {"summaries", summaries}}
        .dump(-1, ' ', false, json::error_handler_t::replace);
  };
  PhaseMapPoint done;
  done.S = 1e-5, done.R = 0.1, done.phi = 0.4, done.eps_end = 0.2, done.state = "succeeded";
  done.cls = "b", done.runner_up = "a \"quoted\" \\ \xff name", done.status = "ok";
  done.confidence = 1.0, done.band_speed_ratio = 1.7300000000000002, done.band_speed_error = 3e-300;
  done.band_speed_transit = -0.5, done.band_speed_transit_error = 12345678.0;
  done.band_speed_early = 2.14, done.band_speed_early_error = 1e-12, done.band_speed_lead = 2.79;
  done.n_reflections = 3, done.progress_eps = 0.2, done.job_id = 42, done.cells_per_unit = 20;
  done.human_label = "c", done.structure = "random", done.point_id = 5;
  PhaseMapPoint queued;
  queued.S = 0.001 + 1e-4 * 7 + (0.09 - 0.001) / 49 * 13, queued.R = 1.0 / 3.0, queued.phi = 0.55, queued.eps_end = 1;
  queued.state = "queued", queued.job_id = 7, queued.cells_per_unit = 8;
  queued.runner_up = "tab\there\x7f";  // only a control character to escape
  queued.point_id = 9;
  PhaseMapPoint replicate = done;  // a second run of done's point, unlabelled by a person
  replicate.job_id = 43, replicate.human_label.reset(), replicate.cls = "c";
  replicate.band_speed_ratio = 1.9, replicate.band_speed_early.reset(), replicate.n_reflections = 4;
  for (const auto& points : {std::vector<PhaseMapPoint>{}, std::vector<PhaseMapPoint>{done, queued},
                             std::vector<PhaseMapPoint>{done, queued, replicate}}) {
    // The same keys, order and values (doubles compared exactly); a number's text may be
    // shorter than nlohmann's, never another double.
    EXPECT_EQ(json::parse(views::phase_map(0.4, points)).dump(), json::parse(slow(0.4, points)).dump());
  }
}
