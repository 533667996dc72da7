// Fork-join over a few threads for the stages of a scan update: private to the library.
#pragma once

#include <cstddef>
#include <exception>
#include <thread>
#include <vector>

namespace ndtom {

/// Runs task(t) for t = 0 .. threads-1, task(0) on the calling thread, and returns when all
/// are done, rethrowing the first exception. A worker that cannot be started (no threads or
/// memory left) has its share run by the caller, so the result never depends on it.
template <class Task>
void runParallel(size_t threads, Task&& task) {
  if (threads <= 1) {
    task(size_t(0));
    return;
  }
  std::vector<std::exception_ptr> errors;
  std::vector<std::thread> workers;
  std::vector<size_t> not_started;
  try {
    errors.resize(threads);
    workers.reserve(threads - 1);
    not_started.reserve(threads - 1);
  } catch (...) {
    for (size_t t = 0; t < threads; ++t) task(t);
    return;
  }
  for (size_t t = 1; t < threads; ++t) {
    try {
      workers.emplace_back([&, t] {
        try {
          task(t);
        } catch (...) {
          errors[t] = std::current_exception();
        }
      });
    } catch (...) {
      not_started.push_back(t);
    }
  }
  try {
    task(size_t(0));
    for (size_t t : not_started) task(t);
  } catch (...) {
    errors[0] = std::current_exception();
  }
  for (std::thread& w : workers) w.join();
  for (const std::exception_ptr& e : errors)
    if (e) std::rethrow_exception(e);
}

/// [begin, end) of part `t` of `n` items split in `parts` near-equal contiguous ranges.
inline std::pair<size_t, size_t> partRange(size_t n, size_t parts, size_t t) {
  return {n * t / parts, n * (t + 1) / parts};
}

}  // namespace ndtom
