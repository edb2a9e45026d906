// The checkpoint store: a checkpoint stored only under the live lease, replacing the older one
// (whose file goes), handed out by find(), read back as stored; resumes recorded under the
// live lease with a 'resumed' event; the checkpoint removed once the job succeeds or fails
// for good and kept when it is released or retried; the folders no row names removed at start.
#include "store/store.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "plan/planner.hpp"
#include "temp_dir.hpp"

using namespace compaction::server;
using nlohmann::json;

namespace {

constexpr Millis t0 = 1'000'000;

StoreConfig config() {
  StoreConfig c;
  c.lease_ms = 10'000;
  c.backoff_base_ms = 1'000;
  c.engine_version = "test-1";
  return c;
}

json one_point(int max_attempts = 3) {
  return {{"name", "t"},
          {"points", {{{"S", 0.01}, {"R", 1e-3}, {"phi", 0.4}}}},
          {"max_attempts", max_attempts},
          {"numerics", {{"cells_per_unit", 6}, {"eps_end", 0.02}}}};
}

std::size_t folders(const std::filesystem::path& root) {
  std::size_t n = 0;
  for (const auto& e : std::filesystem::directory_iterator(root)) n += e.is_directory();
  return n;
}

std::vector<std::string> event_kinds(Store& s, std::int64_t job_id) {
  std::vector<std::string> out;
  const auto detail = s.reads.job(job_id);
  for (const auto& e : detail->events) out.push_back(e.kind);
  return out;
}

struct CheckpointStoreTest : ::testing::Test {
  TempDir dir;
  std::unique_ptr<Store> store = std::make_unique<Store>(dir.file("jobs.db"), config());
  std::filesystem::path root() const { return dir.file("jobs.db.checkpoints"); }
  Lease lease_one(int max_attempts = 3) {
    store->sweeps.create(sweep_rows(plan_sweep(one_point(max_attempts)), "test-1"), t0);
    return *store->queue.lease("w1", "test-1", t0);
  }
};

TEST_F(CheckpointStoreTest, ACheckpointIsStoredOnlyUnderTheLiveLeaseAndReplacesTheOlderOne) {
  const Lease l = lease_one();
  EXPECT_EQ(store->checkpoints.put(l.job_id, "stale", "abc", 10, 0.01, t0 + 1), LeaseCheck::lost);
  EXPECT_EQ(store->checkpoints.put(l.job_id + 7, l.token, "abc", 10, 0.01, t0 + 1),
            LeaseCheck::unknown_job);
  EXPECT_FALSE(store->checkpoints.find(l.job_id));
  EXPECT_EQ(folders(root()), 0u);  // the refused uploads left no file

  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "first", 10, 0.01, t0 + 1), LeaseCheck::ok);
  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "second!", 20, 0.02, t0 + 2), LeaseCheck::ok);
  const auto c = store->checkpoints.find(l.job_id);
  ASSERT_TRUE(c);
  EXPECT_EQ(c->step, 20);
  EXPECT_EQ(c->eps, 0.02);
  EXPECT_EQ(c->size, 7);
  EXPECT_EQ(c->worker, "w1");
  EXPECT_EQ(c->attempt, 1);
  EXPECT_EQ(store->checkpoints.read(*c), "second!");
  EXPECT_EQ(folders(root()), 1u);  // the first one's file is gone
  const auto kinds = event_kinds(*store, l.job_id);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "checkpoint"), 2);
}

TEST_F(CheckpointStoreTest, AResumeIsRecordedUnderTheLiveLeaseWithAnEvent) {
  const Lease l = lease_one();
  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "state", 10, 0.01, t0 + 1), LeaseCheck::ok);
  ASSERT_EQ(store->queue.release(l.job_id, l.token, t0 + 2), LeaseCheck::ok);
  EXPECT_TRUE(store->checkpoints.find(l.job_id)) << "a released job keeps its checkpoint";
  EXPECT_EQ(store->checkpoints.record_resume(l.job_id, l.token, 10, 0.01, t0 + 3), LeaseCheck::lost);

  const Lease again = *store->queue.lease("w2", "test-1", t0 + 4);
  ASSERT_EQ(store->checkpoints.record_resume(again.job_id, again.token, 10, 0.01, t0 + 5),
            LeaseCheck::ok);
  const auto resumes = store->checkpoints.resumes(l.job_id);
  ASSERT_EQ(resumes.size(), 1u);
  EXPECT_EQ(resumes[0].worker, "w2");
  EXPECT_EQ(resumes[0].step, 10);
  EXPECT_EQ(resumes[0].eps, 0.01);
  EXPECT_EQ(resumes[0].at, t0 + 5);
  EXPECT_EQ(event_kinds(*store, l.job_id).back(), "resumed");
}

TEST_F(CheckpointStoreTest, TheCheckpointGoesWhenTheJobSucceedsOrFailsForGood) {
  const Lease l = lease_one(2);
  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "state", 10, 0.01, t0 + 1), LeaseCheck::ok);
  // a retryable failure with attempts left: queued again, the checkpoint stays
  ASSERT_EQ(store->queue.fail(l.job_id, l.token, "crash", true, t0 + 2).state, JobState::queued);
  store->checkpoints.remove_if_done(l.job_id);
  ASSERT_TRUE(store->checkpoints.find(l.job_id));
  // the last attempt fails: failed for good, the checkpoint and its file go
  const Lease last = *store->queue.lease("w1", "test-1", t0 + 60'000);
  ASSERT_EQ(store->queue.fail(last.job_id, last.token, "crash", true, t0 + 60'001).state,
            JobState::failed);
  store->checkpoints.remove_if_done(l.job_id);
  EXPECT_FALSE(store->checkpoints.find(l.job_id));
  EXPECT_EQ(folders(root()), 0u);
}

TEST_F(CheckpointStoreTest, TheLeaseCarriesTheCheckpointAndTheCompletionSaysOneIsToGo) {
  const Lease l = lease_one();
  EXPECT_FALSE(l.checkpoint);
  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "state", 10, 0.01, t0 + 1), LeaseCheck::ok);
  ASSERT_EQ(store->queue.release(l.job_id, l.token, t0 + 2), LeaseCheck::ok);
  const Lease again = *store->queue.lease("w2", "test-1", t0 + 3);
  ASSERT_TRUE(again.checkpoint) << "the lease answer names the checkpoint to go on from";
  EXPECT_EQ(again.checkpoint->step, 10);
  EXPECT_EQ(again.checkpoint->worker, "w1");
  ResultRecord r;
  r.status = "ok";
  r.scene = store->queue.job_scene(again.job_id)->first;
  r.engine_version = "test-1";
  r.source_revision = "abc";
  r.summary = "{}";
  QueueStore::FollowUps follow;
  ASSERT_EQ(store->queue.complete(again.job_id, again.token, r, t0 + 4, std::nullopt, &follow),
            LeaseCheck::ok);
  EXPECT_TRUE(follow.checkpoint);
  EXPECT_FALSE(follow.next) << "not asked for";
}

TEST_F(CheckpointStoreTest, AtStartFoldersNoRowNamesAndCheckpointsOfDoneJobsGo) {
  const Lease l = lease_one(1);
  ASSERT_EQ(store->checkpoints.put(l.job_id, l.token, "state", 10, 0.01, t0 + 1), LeaseCheck::ok);
  // the job fails for good while the removal does not happen (a crash between the two)
  ASSERT_EQ(store->queue.fail(l.job_id, l.token, "crash", false, t0 + 2).state, JobState::failed);
  std::filesystem::create_directories(root() / "job-99-1-s1");  // an upload never committed
  store.reset();
  store = std::make_unique<Store>(dir.file("jobs.db"), config());
  EXPECT_FALSE(store->checkpoints.find(l.job_id));
  EXPECT_EQ(folders(root()), 0u);
}

}  // namespace
