// Group commit: the writes of concurrent callers in one transaction. A caller hands its
// statements in as a work item and blocks; one caller at a time (the leader) takes every item
// waiting, runs them in one write transaction under the writer's lock, each in a savepoint of
// its own, and commits once. The items that arrive while a batch is written form the next
// batch, so nobody waits for company: under light load a batch is one item, under heavy load
// the callers share the commit's WAL frames (the pages they touch in common are written once)
// and the write lock's hand-overs.
//
// An item that throws is rolled back to its savepoint and its caller gets the exception; the
// batch's other items commit. When the transaction itself fails (BEGIN, COMMIT, or an error
// that makes SQLite roll back the whole transaction), every caller of the batch gets that error
// and nothing of the batch is stored.
//
// A work item runs on the leader's thread and must not take the write lock itself.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <mutex>
#include <vector>

#include "store/sqlite.hpp"

namespace compaction::server {

class GroupCommit {
 public:
  GroupCommit(sqlite::Database& writer, std::mutex& write_mutex)
      : writer_(writer), write_mutex_(write_mutex) {}
  GroupCommit(const GroupCommit&) = delete;
  GroupCommit& operator=(const GroupCommit&) = delete;

  // Runs work inside a write transaction shared with the items of concurrent callers; returns
  // once that transaction has committed (visible to readers; durable only after the store's
  // wait_durable), or rethrows the exception of work or of the transaction.
  void run(const std::function<void()>& work);

  // Transactions committed or rolled back so far, and the items they held.
  struct Totals {
    std::uint64_t batches = 0;
    std::uint64_t items = 0;
  };
  Totals totals() const;
  // Callers waiting for the next batch now.
  std::size_t waiting() const;

 private:
  struct Item {
    const std::function<void()>* work = nullptr;
    std::exception_ptr error;
    bool done = false;
  };
  // One transaction for the batch, under the write lock; every error goes to the items, so the
  // leader always gets back to hand the batch over.
  void write(const std::vector<Item*>& batch) noexcept;

  sqlite::Database& writer_;
  std::mutex& write_mutex_;
  mutable std::mutex mutex_;  // guards the members below
  std::condition_variable done_;
  std::vector<Item*> pending_;
  bool leading_ = false;  // a caller is writing a batch now
  Totals totals_;
};

}  // namespace compaction::server
