// The project's performance targets (issue 6), checked on one dataset's runs and printed as
// PASS / FAIL / SKIP lines. Only meaningful on the shared lidar data, single thread, Release.
#pragma once

#include <string>
#include <vector>

#include "run_result.h"

namespace ndtom::bench {

inline constexpr double kTargetResolution = 0.2;     ///< m
inline constexpr double kMaxTimeVsOctomap = 0.1;     ///< NDT-OM ≤ 0.1 × OctoMap
inline constexpr double kMaxTimeVsGrid3d = 1.5;      ///< NDT-OM ≤ 1.5 × COccupancyGridMap3D
inline constexpr double kMaxBytesPerCell = 64;       ///< index included
inline constexpr double kMinTwoThreadSpeedup = 1.6;  ///< 2 threads vs 1, same map bytes
inline constexpr double kMinSimilarity = 0.99;       ///< every speed-up vs the exact path
/// Below this CPU/wall share a single-thread run was preempted (a NOTE is printed).
inline constexpr double kMinCpuPerWall = 0.9;

/// One line per target: "PASS|FAIL|SKIP <target>: <figures>". Single-thread time verdicts
/// use median process CPU time per scan (the wall time of an idle machine, and robust to other
/// processes on a shared one; wall ratios are printed beside them); the thread target uses
/// wall time. A last "NOTE ..." line if the machine was busy during single-thread runs.
std::vector<std::string> checkTargets(const std::vector<RunResult>& runs,
                                      const std::string& dataset);

}  // namespace ndtom::bench
