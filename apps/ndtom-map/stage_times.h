// Wall time of each stage of a run (reading, inserting, each output), in the order run, and
// the process's peak memory after it, for the summary: where a run's time and memory go
// without a profiler.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "ndtom_apps/process_memory.h"

namespace ndtom::mapper {

class StageTimes {
 public:
  struct Stage {
    std::string name;
    double seconds = 0;         ///< wall time
    size_t peak_rss_bytes = 0;  ///< the process's peak resident memory (VmHWM) at its end
  };

  void add(const std::string& stage, double seconds) {
    stages_.push_back({stage, seconds, apps::peakRssBytes()});
  }

  /// Runs `f` and adds its wall time under `stage`; returns what f returns.
  template <class F>
  auto time(const std::string& stage, F&& f) {
    struct Record {  // adds the time on every way out, a throw included
      StageTimes& times;
      const std::string& stage;
      std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
      ~Record() {
        times.add(stage,
                  std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
      }
    } record{*this, stage};
    return f();
  }

  const std::vector<Stage>& stages() const { return stages_; }

 private:
  std::vector<Stage> stages_;
};

}  // namespace ndtom::mapper
