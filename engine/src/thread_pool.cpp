#include "thread_pool.hpp"

namespace compaction {

ThreadPool::ThreadPool(int threads) : size_(threads < 1 ? 1 : threads) {
  for (int i = 1; i < size_; ++i) workers_.emplace_back([this, i] { loop(i); });
}

ThreadPool::~ThreadPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  start_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadPool::run_erased(void (*call)(void*, int), void* fn) {
  {
    std::lock_guard lock(mutex_);
    call_ = call;
    fn_ = fn;
    pending_ = size_ - 1;
    ++generation_;
  }
  start_.notify_all();
  call(fn, 0);
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return pending_ == 0; });
}

void ThreadPool::loop(int index) {
  std::size_t seen = 0;
  for (;;) {
    void (*call)(void*, int);
    void* fn;
    {
      std::unique_lock lock(mutex_);
      start_.wait(lock, [&] { return stop_ || generation_ != seen; });
      if (stop_) return;
      seen = generation_;
      call = call_;
      fn = fn_;
    }
    call(fn, index);
    {
      std::lock_guard lock(mutex_);
      if (--pending_ == 0) done_.notify_one();
    }
  }
}

}  // namespace compaction
