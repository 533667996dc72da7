// Fork-join over a few threads for the stages of a scan update: private to the library.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <mutex>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "support/stage_clock.h"

namespace ndtom {

/// Threads kept from stage to stage and scan to scan: a scan has a dozen parallel stages, and
/// starting a thread costs about as much as a small stage. Waiting threads spin a little
/// before they sleep: waking a sleeping thread costs more than the gap between two stages
/// (doc/benchmarks.md, "Measurements behind the insertion code").
class WorkerPool {
 public:
  WorkerPool() = default;
  WorkerPool(const WorkerPool&) = delete;
  WorkerPool& operator=(const WorkerPool&) = delete;
  ~WorkerPool() {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& w : workers_) w.join();
  }

  /// Runs task(t) for t = 0 .. threads-1, task(0) on the calling thread, and returns when all
  /// are done, rethrowing the first exception. Workers start on first need and stay; a worker
  /// that cannot be started (no threads or memory left) has its share run by the caller, so
  /// the result never depends on it. In a profiled stage (StageClock), the region's wall time
  /// and each task's time are added to the stage.
  template <class Task>
  void run(size_t threads, Task&& task) {
    const OpenStage open = t_open_stage;
    if (!open.profile) return runRound(threads, task);
    std::vector<double> busy;
    try {
      busy.assign(std::max<size_t>(threads, 1), 0.0);
    } catch (...) {  // out of memory: unprofiled
      return runRound(threads, task);
    }
    t_open_stage = {};  // a region inside a task is part of this one
    struct Restore {
      OpenStage open;
      ~Restore() { t_open_stage = open; }
    } restore{open};
    const Clock::time_point start = Clock::now();
    runRound(threads, [&](size_t t) {
      const Clock::time_point task_start = Clock::now();
      task(t);
      busy[t] = secondsSince(task_start);
    });
    const double wall = secondsSince(start);
    StageTimes& stage = *open.get();  // after the tasks: they may have added stages
    stage.parallel_wall_seconds += wall;
    for (const double b : busy) stage.busy_seconds += b;
    ++stage.regions;
  }

 private:
  template <class Task>
  void runRound(size_t threads, Task&& task) {
    if (threads <= 1) {
      task(size_t(0));
      return;
    }
    while (workers_.size() < threads - 1) {
      try {
        // It starts having seen the rounds so far: the next one is its first.
        workers_.emplace_back(
            [this, t = workers_.size() + 1, seen = round_.load()] { work(t, seen); });
      } catch (...) {
        break;
      }
    }
    const size_t helpers = std::min(workers_.size(), threads - 1);
    std::vector<std::exception_ptr> errors;
    try {
      errors.resize(threads);
    } catch (...) {
      for (size_t t = 0; t < threads; ++t) task(t);
      return;
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      invoke_ = [](void* context, size_t t) {
        (*static_cast<std::remove_reference_t<Task>*>(context))(t);
      };
      context_ = &task;
      errors_ = &errors;
      helpers_ = helpers;
      pending_.store(helpers, std::memory_order_relaxed);
      round_.fetch_add(1, std::memory_order_release);
    }
    wake_.notify_all();
    for (size_t t = 0; t < threads; ++t) {
      if (t >= 1 && t <= helpers) continue;  // a worker's
      try {
        task(t);
      } catch (...) {
        errors[t] = std::current_exception();
      }
    }
    if (!spinUntil([&] { return pending_.load(std::memory_order_acquire) == 0; })) {
      std::unique_lock<std::mutex> lock(mutex_);
      done_.wait(lock, [&] { return pending_.load(std::memory_order_acquire) == 0; });
    }
    for (const std::exception_ptr& e : errors)
      if (e) std::rethrow_exception(e);
  }

  /// Spins (pausing) until `ready()` or for kSpin; whether ready() came true.
  template <class Ready>
  static bool spinUntil(Ready&& ready) {
    constexpr std::chrono::microseconds kSpin{200};  // longer than most serial gaps in a scan
    const auto deadline = std::chrono::steady_clock::now() + kSpin;
    for (int i = 1;; ++i) {
      if (ready()) return true;
      if (i % 64 == 0 && std::chrono::steady_clock::now() > deadline) return false;
#if defined(__x86_64__) || defined(__i386__)
      __builtin_ia32_pause();
#endif
    }
  }

  void work(size_t t, uint64_t seen) {
    for (;;) {
      spinUntil([&] { return round_.load(std::memory_order_relaxed) != seen; });
      std::unique_lock<std::mutex> lock(mutex_);  // the round's fields are read under it
      wake_.wait(lock, [&] { return stop_ || round_.load(std::memory_order_relaxed) != seen; });
      if (stop_) return;
      seen = round_.load(std::memory_order_relaxed);
      if (t > helpers_) continue;  // not needed this round
      void (*invoke)(void*, size_t) = invoke_;
      void* context = context_;
      std::vector<std::exception_ptr>* errors = errors_;
      lock.unlock();
      try {
        invoke(context, t);
      } catch (...) {
        (*errors)[t] = std::current_exception();  // this thread's slot only
      }
      if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
        lock.lock();  // the caller checks pending_ under it before it sleeps
        done_.notify_one();
      }
    }
  }

  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;  ///< workers_[i] runs task i + 1
  void (*invoke_)(void*, size_t) = nullptr;
  void* context_ = nullptr;
  std::vector<std::exception_ptr>* errors_ = nullptr;
  size_t helpers_ = 0;              ///< workers taking part in this round: tasks 1 .. helpers_
  std::atomic<size_t> pending_{0};  ///< of them, still running
  std::atomic<uint64_t> round_{0};
  bool stop_ = false;
};

/// Threads for `items` of work, at least `min_items_per_thread` each (starting a thread costs
/// more than a small part's work), at least one, at most `max_threads`.
inline size_t threadsFor(size_t items, size_t min_items_per_thread, size_t max_threads) {
  return std::clamp<size_t>(items / min_items_per_thread, 1, max_threads);
}

/// The threads a function may use: up to `threads` of `pool`. Results never depend on them.
struct Threads {
  WorkerPool& pool;
  size_t threads = 1;
  /// threadsFor(items, min_items_per_thread, threads).
  size_t forItems(size_t items, size_t min_items_per_thread) const {
    return threadsFor(items, min_items_per_thread, threads);
  }
};

/// [begin, end) of part `t` of `n` items split in `parts` near-equal contiguous ranges.
inline std::pair<size_t, size_t> partRange(size_t n, size_t parts, size_t t) {
  return {n * t / parts, n * (t + 1) / parts};
}

}  // namespace ndtom
