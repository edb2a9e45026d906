// A fixed set of threads that run one function together, for the stages of a time step.
// With one thread everything runs inline on the caller: no synchronisation at all.
//
// A step hands the threads work every few hundred microseconds, four to six times per step. A
// thread put to sleep takes tens of microseconds to wake (longer on a virtual machine), which
// cost a quarter of the gain of a second thread, so a waiting thread spins for kSpin first and
// only then sleeps (C++20 atomic wait: a futex on Linux).
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <thread>
#include <type_traits>
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

  // How long a waiting thread spins before it sleeps.
  static constexpr std::chrono::microseconds kSpin{200};

 private:
  void run_erased(void (*call)(void*, int), void* fn);
  void loop(int index);
  int size_;
  std::vector<std::thread> workers_;
  void (*call_)(void*, int) = nullptr;  // published by the release of generation_
  void* fn_ = nullptr;
  std::atomic<unsigned> generation_{0};  // one more for every run and for the stop
  std::atomic<int> pending_{0};          // workers still running the current function
  std::atomic<bool> stop_{false};
};

}  // namespace compaction
