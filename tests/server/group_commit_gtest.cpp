// GroupCommit on a real SQLite file: the callers that arrive while a batch is written share the
// next transaction; an item that throws is rolled back alone and its caller gets the exception;
// a transaction that fails at its commit stores nothing of its batch and tells every caller.
#include "store/group_commit.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "temp_dir.hpp"

using namespace compaction::server;

namespace {

struct Fixture {
  TempDir dir;
  sqlite::Database db{dir.file("t.db")};
  std::mutex write_mutex;
  GroupCommit group{db, write_mutex};

  Fixture() {
    db.exec_script(
        "CREATE TABLE parent (id INTEGER PRIMARY KEY);"
        "CREATE TABLE rows (x INTEGER UNIQUE,"
        " parent INTEGER REFERENCES parent (id) DEFERRABLE INITIALLY DEFERRED);"
        "INSERT INTO parent VALUES (1);");
  }
  void insert(std::int64_t x, std::int64_t parent = 1) {
    db.prepare("INSERT INTO rows (x, parent) VALUES (?, ?)").bind(1, x).bind(2, parent).run();
  }
  std::int64_t count() {
    auto s = db.prepare("SELECT count(*) FROM rows");
    s.step();
    return s.int64(0);
  }
  bool has(std::int64_t x) { return db.has_row("SELECT 1 FROM rows WHERE x = ?", x); }
  // Holds the writer's lock while `callers` threads call run(): the first becomes the leader of
  // a batch of its own and waits for the lock; the others queue behind it. Lets go once all of
  // them wait, so they form exactly one second batch.
  template <typename Work>
  void queue_behind_a_held_lock(int callers, Work work) {
    std::vector<std::thread> threads;
    {
      std::lock_guard hold(write_mutex);
      for (int i = 0; i < callers; ++i) threads.emplace_back([&, i] { work(i); });
      const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(30);
      while (group.waiting() < static_cast<std::size_t>(callers - 1) &&
             std::chrono::steady_clock::now() < give_up) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      }
      EXPECT_EQ(group.waiting(), static_cast<std::size_t>(callers - 1));
    }
    for (auto& t : threads) t.join();
  }
};

}  // namespace

TEST(GroupCommit, CallersThatArriveDuringABatchShareTheNextTransaction) {
  Fixture f;
  const std::uint64_t commits_before = f.db.commits();
  f.queue_behind_a_held_lock(8, [&](int i) { f.group.run([&] { f.insert(i); }); });
  EXPECT_EQ(f.count(), 8);
  const GroupCommit::Totals t = f.group.totals();
  EXPECT_EQ(t.batches, 2u);  // the leader alone, then the seven that queued behind it
  EXPECT_EQ(t.items, 8u);
  EXPECT_EQ(f.db.commits() - commits_before, 2u);
}

TEST(GroupCommit, AnItemThatThrowsIsRolledBackAloneAndItsCallerGetsTheError) {
  Fixture f;
  std::atomic<int> errors{0};
  f.queue_behind_a_held_lock(6, [&](int i) {
    try {
      f.group.run([&] {
        f.insert(i);
        if (i % 2 == 1) throw std::runtime_error("item " + std::to_string(i));
      });
    } catch (const std::runtime_error& e) {
      EXPECT_EQ(std::string(e.what()), "item " + std::to_string(i));
      ++errors;
    }
  });
  EXPECT_EQ(errors.load(), 3);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(f.has(i), i % 2 == 0) << i;
}

TEST(GroupCommit, ABatchOfOneThatThrowsStoresNothingAndTheNextOneWorks) {
  Fixture f;
  EXPECT_THROW(f.group.run([&] {
    f.insert(1);
    f.insert(1);  // the UNIQUE constraint refuses it
  }),
               sqlite::Error);
  EXPECT_EQ(f.count(), 0);
  f.group.run([&] { f.insert(2); });
  EXPECT_TRUE(f.has(2));
}

TEST(GroupCommit, ACommitThatFailsStoresNothingOfItsBatchAndTellsEveryCaller) {
  Fixture f;
  std::atomic<int> errors{0};
  // Item 0 names a parent that does not exist: the deferred foreign key fails the COMMIT, not
  // the item, so the whole batch is refused.
  f.queue_behind_a_held_lock(5, [&](int i) {
    try {
      f.group.run([&] { f.insert(i, i == 0 ? 99 : 1); });
    } catch (const sqlite::Error&) {
      ++errors;
    }
  });
  // Item 0 is the leader's batch of one (one error, four rows) or one of the four queued behind
  // it (four errors, the leader's row).
  EXPECT_TRUE(errors.load() == 1 || errors.load() == 4) << errors.load();
  EXPECT_FALSE(f.has(0));
  EXPECT_EQ(f.count(), 5 - errors.load());
  f.group.run([&] { f.insert(10); });  // the writer is usable afterwards
  EXPECT_TRUE(f.has(10));
}
