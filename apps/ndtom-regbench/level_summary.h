// The figures per system, threads and error level that the tables, the CSV and the plot show.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "system_run.h"

namespace ndtom::regbench {

/// Mean of one pyramid level over a level's registrations but the system's first call
/// (NdtRegistration only).
struct PyramidLevelTime {
  double resolution = 0;  ///< m
  double mean_seconds = 0;
  double mean_iterations = 0;
};

/// Verdicts of a system that gives one (NdtRegistration): counts over the level's trials.
struct VerdictCounts {
  int converged = 0;
  int wrong_converged = 0;  ///< converged, but not a success: the worst outcome
  int false_failures = 0;   ///< a success reported as failed
};

struct LevelSummary {
  std::string label;  ///< system label
  SystemKind kind = SystemKind::NdtomP2D;
  int threads = 1;
  ErrorLevel level;
  int trials = 0, successes = 0;
  /// Of the successes; NaN when there is none.
  double median_error_m = 0, median_error_deg = 0;
  /// Per registration, the system's first call left out; NaN when no call is left.
  double median_ms = 0, p95_ms = 0, median_cpu_ms = 0;
  double mean_ms = 0;  ///< to set beside the mean time of the pyramid levels
  std::optional<VerdictCounts> verdicts;
  std::vector<PyramidLevelTime> pyramid;  ///< coarse to fine; empty for the peers

  double successRate() const { return trials > 0 ? double(successes) / trials : 0; }
};

/// One summary per error level of `levels` (in their order).
std::vector<LevelSummary> summarize(const SystemRun& run, const std::vector<ErrorLevel>& levels);

/// Median and p95 time (ms) over all of a run's registrations but the first call.
struct OverallTimes {
  double median_ms = 0, p95_ms = 0, median_cpu_ms = 0;
};
OverallTimes overallTimes(const SystemRun& run);

}  // namespace ndtom::regbench
