// GroupSync: a caller returns only after a sync that started after its call; concurrent callers
// share syncs; a failed sync fails every caller it was to cover, and the next one works.
#include "store/group_sync.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <set>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace compaction::server;

namespace {

// A stand-in for the disk: what was written, and what a sync made durable (the writes made
// before the sync started).
struct FakeDisk {
  std::mutex mutex;
  std::set<int> written, durable;
  std::atomic<int> syncs{0};
  std::atomic<int> fail_next{0};

  void sync() {
    std::set<int> covered;
    {
      std::lock_guard lock(mutex);
      covered = written;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // a flush takes a while
    ++syncs;
    if (fail_next.exchange(0)) throw std::runtime_error("EIO");
    std::lock_guard lock(mutex);
    durable.insert(covered.begin(), covered.end());
  }
};

TEST(GroupSync, EachCallerWaitsForASyncThatStartedAfterItsWrites) {
  FakeDisk disk;
  GroupSync group([&] { disk.sync(); });
  constexpr int threads = 16, writes = 20;
  std::atomic<int> not_durable{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      for (int i = 0; i < writes; ++i) {
        const int id = t * writes + i;
        {
          std::lock_guard lock(disk.mutex);
          disk.written.insert(id);
        }
        group.wait();
        std::lock_guard lock(disk.mutex);
        if (!disk.durable.count(id)) ++not_durable;
      }
    });
  }
  for (auto& th : pool) th.join();
  EXPECT_EQ(not_durable.load(), 0);
  // Shared: far fewer syncs than callers (16 callers at a time, one sync per round).
  EXPECT_LT(disk.syncs.load(), threads * writes / 2);
  EXPECT_EQ(group.rounds(), static_cast<std::uint64_t>(disk.syncs.load()));
}

TEST(GroupSync, ALoneCallerRunsItsOwnSync) {
  FakeDisk disk;
  GroupSync group([&] { disk.sync(); });
  group.wait();
  group.wait();
  EXPECT_EQ(disk.syncs.load(), 2);
}

TEST(GroupSync, AFailedSyncFailsEveryCallerItCovered) {
  FakeDisk disk;
  GroupSync group([&] { disk.sync(); });
  disk.fail_next = 1;
  EXPECT_THROW(group.wait(), std::runtime_error);
  group.wait();  // the next round works

  // Callers that joined a round while the one before it ran: when their round fails, all of
  // them throw, and whoever returns has its write on disk.
  std::atomic<int> threw{0}, not_durable{0};
  std::vector<std::thread> pool;
  for (int t = 0; t < 8; ++t) {
    pool.emplace_back([&, t] {
      {
        std::lock_guard lock(disk.mutex);
        disk.written.insert(1000 + t);
      }
      if (t == 4) disk.fail_next = 1;  // the round running now or the next one fails
      try {
        group.wait();
      } catch (const std::runtime_error&) {
        ++threw;
        return;
      }
      std::lock_guard lock(disk.mutex);
      if (!disk.durable.count(1000 + t)) ++not_durable;
    });
  }
  for (auto& th : pool) th.join();
  EXPECT_GE(threw.load(), 1);
  EXPECT_EQ(not_durable.load(), 0);
}

}  // namespace
