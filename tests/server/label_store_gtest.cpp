// Human labels in a real SQLite store (label_store.hpp): a label needs a result, replaces the
// previous one, can be cleared; every change is in the audit with who, why, when, the label
// before and the classifier's; the reads carry the label beside the classifier's.
#include <gtest/gtest.h>

#include "plan/planner.hpp"
#include "store/store.hpp"
#include "temp_dir.hpp"
#include "views/views.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

constexpr Millis t0 = 1'000'000;

struct LabelTest : ::testing::Test {
  TempDir dir;
  Store store{dir.file("labels.db"), [] {
                StoreConfig c;
                c.engine_version = "test-1";
                return c;
              }()};
  std::int64_t done = 0, queued = 0;

  void SetUp() override {
    const json body = {{"name", "t"},
                       {"points", {{{"S", 0.05}, {"R", 1e-3}, {"phi", 0.4}}, {{"S", 0.06}, {"R", 1e-3}, {"phi", 0.4}}}},
                       {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}};
    store.sweeps.create(sweep_rows(plan_sweep(body), "test-1"), t0);
    const auto l = store.queue.lease("w", "test-1", t0);
    ResultRecord r;
    r.status = "ok";
    r.scene = l->scene;
    r.engine_version = "test-1";
    r.source_revision = "abc";
    r.cls = "a";
    r.confidence = 0.6;
    r.summary = "{}";
    ASSERT_EQ(store.queue.complete(l->job_id, l->token, r, t0 + 1), LeaseCheck::ok);
    done = l->job_id;
    queued = done == 1 ? 2 : 1;
  }
};

}  // namespace

TEST_F(LabelTest, ALabelNeedsAJobWithAResult) {
  EXPECT_EQ(store.labels.set(99, {"b", "r", "ana", t0, "open", std::nullopt}), LabelOutcome::unknown_job);
  EXPECT_EQ(store.labels.set(queued, {"b", "r", "ana", t0, "open", std::nullopt}), LabelOutcome::no_result);
  EXPECT_EQ(store.labels.clear(done, "", "ana", "open", t0), LabelOutcome::not_labelled);
  std::int64_t total = -1;
  EXPECT_TRUE(store.labels.audit(std::nullopt, 10, 0, total).empty());
  EXPECT_EQ(total, 0);
}

TEST_F(LabelTest, SetReplaceAndClearAreAuditedWithWhoWhyWhenAndTheLabelsBefore) {
  ASSERT_EQ(store.labels.set(done, {"b", "reflects twice", "ana", t0 + 10, "open", std::nullopt}), LabelOutcome::ok);
  ASSERT_EQ(store.labels.set(done, {"c", "fronts from both plates", "ben", t0 + 20, "submit:ben", std::nullopt}),
            LabelOutcome::ok);
  json j = views::job_detail(*store.reads.job(done));
  EXPECT_EQ(j["human_label"], (json{{"label", "c"}, {"reason", "fronts from both plates"}, {"by", "ben"},
                                    {"at", t0 + 20}, {"token", "submit:ben"}, {"imported_at", nullptr}}));
  EXPECT_EQ(j["result"]["class"], "a") << "the classifier's label stays";
  const json map = json::parse(views::phase_map(0.4, store.reads.phase_map(0.4, std::nullopt)));
  for (const json& p : map["points"]) {
    EXPECT_EQ(p["human_label"], p["job_id"] == done ? json("c") : json(nullptr));
  }

  ASSERT_EQ(store.labels.clear(done, "the classifier was right", "ana", "open", t0 + 30), LabelOutcome::ok);
  EXPECT_TRUE(views::job_detail(*store.reads.job(done))["human_label"].is_null());
  std::int64_t total = 0;
  const auto changes = store.labels.audit(done, 10, 0, total);
  ASSERT_EQ(total, 3);
  EXPECT_EQ(changes[0].action, "cleared");  // newest first
  EXPECT_EQ(changes[0].previous_label, "c");
  EXPECT_EQ(changes[0].token, "open") << "the token of the request that cleared it";
  EXPECT_EQ(changes[1].token, "submit:ben");
  EXPECT_EQ(changes[0].by, "ana");
  EXPECT_EQ(changes[1].action, "set");
  EXPECT_EQ(changes[1].label, "c");
  EXPECT_EQ(changes[1].previous_label, "b");
  EXPECT_EQ(changes[2].label, "b");
  EXPECT_FALSE(changes[2].previous_label);
  EXPECT_EQ(changes[2].classifier_label, "a");
  EXPECT_EQ(changes[2].at, t0 + 10);
  EXPECT_EQ(store.labels.audit(queued, 10, 0, total).size(), 0u);
  EXPECT_EQ(store.labels.audit(std::nullopt, 1, 1, total).size(), 1u);
  EXPECT_EQ(total, 3);
}

TEST_F(LabelTest, TheSchemaRefusesAClassOutsideAToF) {
  EXPECT_THROW(store.labels.set(done, {"g", "r", "ana", t0, "open", std::nullopt}), sqlite::Error);
  std::int64_t total = 0;
  store.labels.audit(std::nullopt, 10, 0, total);
  EXPECT_EQ(total, 0) << "the refused change left no audit row";
}
