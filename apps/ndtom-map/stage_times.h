// Wall time of each stage of a run (reading, inserting, each output), in the order run, and
// the process's peak memory after it, for the summary: where a run's time and memory go
// without a profiler.
#pragma once

#include <chrono>
#include <string>
#include <utility>
#include <vector>

#include "ndtom_apps/process_memory.h"

namespace ndtom::mapper {

class StageTimes {
 public:
  void add(const std::string& stage, double seconds) {
    seconds_.emplace_back(stage, seconds);
    peak_rss_.emplace_back(stage, apps::peakRssBytes());
  }

  /// Runs `f` and adds its wall time under `stage`; returns what f returns.
  template <class F>
  auto time(const std::string& stage, F&& f) {
    struct Record {  // adds the time on every way out, a throw included
      StageTimes& times;
      const std::string& stage;
      std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
      ~Record() {
        times.add(stage, std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                             .count());
      }
    } record{*this, stage};
    return f();
  }

  const std::vector<std::pair<std::string, double>>& seconds() const { return seconds_; }
  /// Peak resident bytes of the process at the end of each stage (never decreasing).
  const std::vector<std::pair<std::string, size_t>>& peakRss() const { return peak_rss_; }

 private:
  std::vector<std::pair<std::string, double>> seconds_;
  std::vector<std::pair<std::string, size_t>> peak_rss_;
};

}  // namespace ndtom::mapper
