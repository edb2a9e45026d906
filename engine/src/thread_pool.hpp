// A fixed set of threads that run one function together, for the stages of a time step.
// With one thread everything runs inline on the caller: no synchronisation at all.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <type_traits>
#include <mutex>
#include <thread>
#include <vector>

namespace compaction {

class ThreadPool {
 public:
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;

  int size() const { return size_; }
  // Runs fn(thread_index) on every thread (the caller is thread 0) and waits for all.
  // Takes the callable by reference, so a step allocates nothing.
  template <typename Fn>
  void run(Fn&& fn) {
    if (size_ == 1) return fn(0);
    run_erased([](void* f, int t) { (*static_cast<std::remove_reference_t<Fn>*>(f))(t); },
               static_cast<void*>(&fn));
  }

  // The share [begin, end) of n items that thread t of this pool works on.
  std::size_t begin(std::size_t n, int t) const { return n * t / size_; }
  std::size_t end(std::size_t n, int t) const { return n * (t + 1) / size_; }

 private:
  void run_erased(void (*call)(void*, int), void* fn);
  void loop(int index);
  int size_;
  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_, done_;
  void (*call_)(void*, int) = nullptr;
  void* fn_ = nullptr;
  std::size_t generation_ = 0;
  int pending_ = 0;
  bool stop_ = false;
};

}  // namespace compaction
