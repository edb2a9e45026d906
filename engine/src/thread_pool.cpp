#include "thread_pool.hpp"

namespace compaction {

namespace {

// Waits until value != old: spins for ThreadPool::kSpin, then sleeps on the atomic.
template <typename T>
T wait_change(const std::atomic<T>& value, T old) {
  T now = value.load(std::memory_order_acquire);
  if (now != old) return now;
  const auto until = std::chrono::steady_clock::now() + ThreadPool::kSpin;
  for (unsigned i = 1; (now = value.load(std::memory_order_acquire)) == old; ++i) {
#if defined(__x86_64__) || defined(__i386__)
    __builtin_ia32_pause();
#endif
    if (i % 64 == 0 && std::chrono::steady_clock::now() > until) {
      value.wait(old, std::memory_order_acquire);
    }
  }
  return now;
}

}  // namespace

ThreadPool::ThreadPool(int threads) : size_(threads < 1 ? 1 : threads) {
  for (int i = 1; i < size_; ++i) workers_.emplace_back([this, i] { loop(i); });
}

ThreadPool::~ThreadPool() {
  stop_.store(true, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (auto& w : workers_) w.join();
}

void ThreadPool::run_erased(void (*call)(void*, int), void* fn) {
  call_ = call;
  fn_ = fn;
  pending_.store(size_ - 1, std::memory_order_relaxed);
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  call(fn, 0);
  for (int left = pending_.load(std::memory_order_acquire); left != 0;) {
    left = wait_change(pending_, left);
  }
}

void ThreadPool::loop(int index) {
  unsigned seen = 0;  // generation_ at construction, before any run
  for (;;) {
    seen = wait_change(generation_, seen);
    if (stop_.load(std::memory_order_relaxed)) return;
    call_(fn_, index);
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) pending_.notify_one();
  }
}

}  // namespace compaction
