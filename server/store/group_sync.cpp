#include "store/group_sync.hpp"

namespace compaction::server {

void GroupSync::wait() {
  std::unique_lock lock(mutex_);
  if (!next_) next_ = std::make_shared<Round>();
  const std::shared_ptr<Round> round = next_;
  while (!round->done) {
    if (syncing_) {  // a round that may have started before this caller's writes
      done_cv_.wait(lock);
      continue;
    }
    // This caller leads its round: every member arrived before this point.
    next_.reset();
    syncing_ = true;
    lock.unlock();
    std::exception_ptr error;
    try {
      sync_();
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    syncing_ = false;
    ++rounds_;
    round->error = error;
    round->done = true;
    done_cv_.notify_all();
  }
  if (round->error) std::rethrow_exception(round->error);
}

std::uint64_t GroupSync::rounds() const {
  std::lock_guard lock(mutex_);
  return rounds_;
}

}  // namespace compaction::server
