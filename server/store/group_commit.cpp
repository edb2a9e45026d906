#include "store/group_commit.hpp"

namespace compaction::server {

void GroupCommit::run(const std::function<void()>& work) {
  Item me;
  me.work = &work;
  std::unique_lock lock(mutex_);
  pending_.push_back(&me);
  while (!me.done) {
    if (leading_) {
      done_.wait(lock);
      continue;
    }
    leading_ = true;
    std::vector<Item*> batch;
    batch.swap(pending_);
    lock.unlock();
    write(batch);
    lock.lock();
    for (Item* item : batch) item->done = true;
    ++totals_.batches;
    totals_.items += batch.size();
    leading_ = false;
    done_.notify_all();
  }
  if (me.error) std::rethrow_exception(me.error);
}

void GroupCommit::write(const std::vector<Item*>& batch) noexcept {
  std::lock_guard lock(write_mutex_);
  try {
    sqlite::Transaction tx(writer_);
    // A batch of one needs no savepoint: its error rolls the transaction back.
    const bool savepoints = batch.size() > 1;
    for (Item* item : batch) {
      if (savepoints) writer_.prepare("SAVEPOINT item").run();
      try {
        (*item->work)();
      } catch (...) {
        item->error = std::current_exception();
        if (!savepoints) return;
        writer_.prepare("ROLLBACK TO item").run();
      }
      if (savepoints) writer_.prepare("RELEASE item").run();
    }
    tx.commit();
  } catch (...) {
    for (Item* item : batch) {
      if (!item->error) item->error = std::current_exception();
    }
  }
}

GroupCommit::Totals GroupCommit::totals() const {
  std::lock_guard lock(mutex_);
  return totals_;
}

std::size_t GroupCommit::waiting() const {
  std::lock_guard lock(mutex_);
  return pending_.size();
}

}  // namespace compaction::server
