// What one system did on one dataset at one resolution, and the figures derived from it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bench_options.h"
#include "map_comparison.h"
#include "mapping_system.h"
#include "ndtom/support/stage_profile.h"

namespace ndtom::bench {

struct RunResult {
  std::string dataset;
  std::string label;  ///< system label, e.g. "ndtom-point/t1"
  SystemKind kind = SystemKind::NdtomPerPoint;
  int threads = 1;
  double resolution = 0;                      ///< m
  int repeats = 0;                            ///< full runs pooled in scan_seconds
  std::vector<double> scan_seconds;           ///< insertion time of every scan of every repeat
  std::vector<double> scan_cpu_seconds;       ///< process CPU time of the same insertions
  std::vector<double> repeat_median_seconds;  ///< one per repeat: the run-to-run noise
  uint64_t points = 0;                        ///< points given per repeat (sum over scans)
  uint64_t voxel_visits = 0;                  ///< free-space voxel visits per repeat
  MapSize map;                                ///< after the last repeat
  size_t peak_rss_delta = 0;                  ///< largest VmHWM increase over a repeat (bytes)
  bool peak_rss_valid = false;
  /// NDT-OM speed-ups only: against the plain exact path (ndtom-point/t1) ...
  std::optional<MapComparison> vs_exact;
  /// ... and, for threads > 1, against the same ray mode on one thread (must be identical).
  std::optional<MapComparison> vs_one_thread;
  /// For threads > 1: one thread's insertion time over this one's, the two replayed side by
  /// side in turns (runPaired), so that load on a shared machine falls on both alike.
  std::optional<double> paired_speedup;
  /// NDT-OM: where the time of every timed call went, stage by stage (all repeats).
  StageProfile stages;
  /// Registration runs, threads > 1: every pose bit for bit the one-thread run's.
  std::optional<bool> same_poses_as_t1;

  double medianSeconds() const;
  /// Median process CPU time per scan: unlike wall time, not inflated when other processes
  /// take the core (a cross-check on a shared machine; meaningless for threads > 1).
  double medianCpuSeconds() const;
  double p95Seconds() const;
  double totalSeconds() const;
  double totalCpuSeconds() const;
  /// Process CPU time over wall time of the insertions: ~1 for one thread on an idle core,
  /// below 1 when other processes took the core, ~threads when threads run in parallel.
  double cpuPerWall() const;
  double pointsPerSecond() const;
  double visitsPerSecond() const;
  double bytesPerCell() const;
};

/// The run of `label` on `dataset` at `resolution`, or nullptr.
const RunResult* findRun(const std::vector<RunResult>& runs, const std::string& dataset,
                         double resolution, const std::string& label);

}  // namespace ndtom::bench
