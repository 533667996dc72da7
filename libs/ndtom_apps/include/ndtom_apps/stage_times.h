// Wall time of each stage of a run (reading, inserting, each output), when it ended, and the
// process's peak memory then, for the summary: where a run's time and memory go without a
// profiler. Stages run in parallel are timed apart and joined in the order they ended.
#pragma once

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

#include "ndtom_apps/process_clock.h"
#include "ndtom_apps/process_memory.h"

namespace ndtom::apps {

class StageTimes {
 public:
  using Clock = std::chrono::steady_clock;

  struct Stage {
    std::string name;
    double seconds = 0;         ///< wall time
    double end_s = 0;           ///< when it ended, from the origin
    size_t peak_rss_bytes = 0;  ///< the process's peak resident memory (VmHWM) at its end
  };

  /// Stages' ends are counted from `origin` (the run's start).
  explicit StageTimes(Clock::time_point origin) : origin_(origin) {}

  Clock::time_point origin() const { return origin_; }

  /// A stage of `seconds` that ends now.
  void add(const std::string& stage, double seconds) {
    stages_.push_back({stage, seconds, secondsSince(origin_), apps::peakRssBytes()});
  }

  /// Runs `f` and adds its wall time under `stage`; returns what f returns.
  template <class F>
  auto time(const std::string& stage, F&& f) {
    struct Record {  // adds the time on every way out, a throw included
      StageTimes& times;
      const std::string& stage;
      Clock::time_point start = Clock::now();
      ~Record() { times.add(stage, secondsSince(start)); }
    } record{*this, stage};
    return f();
  }

  /// Joins `other`'s stages (timed in parallel with these, from the same origin) to these,
  /// all in the order they ended.
  void merge(const StageTimes& other) {
    stages_.insert(stages_.end(), other.stages_.begin(), other.stages_.end());
    std::stable_sort(stages_.begin(), stages_.end(),
                     [](const Stage& a, const Stage& b) { return a.end_s < b.end_s; });
  }

  const std::vector<Stage>& stages() const { return stages_; }

 private:
  Clock::time_point origin_;
  std::vector<Stage> stages_;
};

}  // namespace ndtom::apps
