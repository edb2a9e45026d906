// Group commit for fsyncs: callers that need what they wrote to be on disk wait for one sync
// that started after their writes, and one sync serves every caller that arrived before it
// started. Under concurrent requests the disk sees one flush per round instead of one per
// request; a lone caller waits for exactly its own sync, as without the group.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>

namespace compaction::server {

class GroupSync {
 public:
  // sync: makes durable everything written (by any thread) before it was called; throws on an
  // I/O error.
  explicit GroupSync(std::function<void()> sync) : sync_(std::move(sync)) {}
  GroupSync(const GroupSync&) = delete;
  GroupSync& operator=(const GroupSync&) = delete;

  // Returns once a sync that started after this call has finished: everything the calling
  // thread wrote before the call is then on disk. When that sync fails, every caller it was
  // to cover throws its error (none of them is told its writes are on disk).
  void wait();

  // Syncs run so far (for tests and the benchmark's notes).
  std::uint64_t rounds() const;

 private:
  // One sync and the callers it covers: those that arrived before it started.
  struct Round {
    bool done = false;
    std::exception_ptr error;
  };

  const std::function<void()> sync_;
  mutable std::mutex mutex_;
  std::condition_variable done_cv_;
  std::shared_ptr<Round> next_;  // the round new callers join; it starts when the running ends
  bool syncing_ = false;
  std::uint64_t rounds_ = 0;
};

}  // namespace compaction::server
