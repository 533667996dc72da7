// The online loop of ndtom-slam: every scan of a source located in the map built so far,
// its pose rounded to what the trajectory file holds, then inserted there.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "loop_closure.h"
#include "ndtom/online/online_mapper.h"
#include "ndtom_apps/progress.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::slam {

struct SlamScan {
  std::string name;
  size_t points = 0;       ///< read
  ndtom::OnlineStep step;  ///< pose as PREFIX.tum holds it (after optimization, with loops)
  /// Where the run put the scan when it was taken: after the loop closures so far, in the
  /// graph's frame (odometry goes on in it once a loop closes).
  Eigen::Isometry3d live = Eigen::Isometry3d::Identity();
  /// Odometry's own pose, had no loop ever closed (before optimization).
  Eigen::Isometry3d odometry = Eigen::Isometry3d::Identity();
  std::string tum_line;                                        ///< "t x y z qx qy qz qw"
};

struct SlamResult {
  std::vector<SlamScan> scans;
  ndtom::NdtMap map;
  ndtom::InsertionReport points;             ///< of the inserted scans
  std::vector<Eigen::Vector3d> sensor_path;  ///< sensor origins of the inserted scans
  bool odometry_used = false;
  apps::SourceSkips skips;
  double seconds = 0;                      ///< the whole loop, reading included
  std::optional<LoopClosureReport> loops;  ///< with loop closure
  double rebuild_seconds = 0;  ///< the exact map at the optimized poses (reading included)
  size_t count(ndtom::OnlineOutcome outcome) const;
};

/// Maps every scan of `source` without its poses. Throws apps::InputError for unreadable data
/// or a scan the map cannot take (memory budget, time going backwards), naming the scan.
SlamResult runOnline(apps::ScanSource& source, const ndtom::OnlineMapperOptions& options,
                     const LoopClosureOptions& loops, apps::Progress& progress);

/// With loop closure: the map made again from `source` (the same scans, read again), each
/// inserted at its optimized pose as the mapper would (what ndtom-map --poses does).
void rebuildAtOptimizedPoses(apps::ScanSource& source, const ndtom::OnlineMapperOptions& options,
                             SlamResult& result, apps::Progress& progress);

/// "t x y z qx qy qz qw" with every number printed so that it reads back bit for bit, and
/// the pose those numbers stand for (what ndtom-map --poses will use).
std::string tumLine(double time, const Eigen::Isometry3d& pose, Eigen::Isometry3d* as_read);

}  // namespace ndtom::slam
