// What ndtom-slam writes beside ndtom-map's outputs: the trajectory (TUM) and the summary
// with per-scan registration figures; and the short text for the terminal.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "ndtom_apps/output_files.h"
#include "ndtom_apps/run_budget.h"
#include "ndtom_eval/trajectory_error.h"
#include "slam_loop.h"
#include "slam_options.h"

namespace ndtom::slam {

/// One line per scan, lost ones at their predicted pose (line i is scan i).
std::string trajectoryTum(const SlamResult& result);
/// The same before the pose graph's optimization (odometry alone), with loop closure.
std::string odometryTum(const SlamResult& result);

struct SlamSummary {
  const SlamOptions* options = nullptr;
  std::string source_description;
  const SlamResult* result = nullptr;
  const ndtom::NdtMap* map = nullptr;  ///< the map written (moved out of the result)
  std::optional<ndtom::TrajectoryError> reference_error;  ///< with --reference
  /// With loop closure and --reference: the odometry's, before optimization.
  std::optional<ndtom::TrajectoryError> odometry_reference_error;
  /// With loop closure and --reference: the poses as the run knew them when each scan came.
  std::optional<ndtom::TrajectoryError> live_reference_error;
  double total_seconds = 0;
  size_t peak_rss = 0;
  mapper::RunBudget budget;  ///< the map's memory budget and why
  std::vector<apps::WrittenFile> files;
};

std::string summaryJson(const SlamSummary& summary);
std::string summaryText(const SlamSummary& summary);

}  // namespace ndtom::slam
