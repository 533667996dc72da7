// The scans every system replays: world-frame points and the sensor origin, loaded once and
// prepared before any timing so that all systems get exactly the same input.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace ndtom::bench {

struct Scan {
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< sensor position, world frame (m)
  std::vector<Eigen::Vector3d> points;               ///< world frame, finite, not at the origin
  /// Sensor -> world (its translation is `origin`): registration takes the scan back to the
  /// sensor frame.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

struct ScanSet {
  std::string name;  ///< short label used in tables and file names
  std::vector<Scan> scans;
  size_t dropped_points = 0;  ///< non-finite or at the sensor origin, removed for all systems

  size_t totalPoints() const;
};

/// Axis-aligned box (m).
struct Box {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(1e300);
  Eigen::Vector3d max = Eigen::Vector3d::Constant(-1e300);
  void extend(const Eigen::Vector3d& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

/// Box holding every sensor origin and every ray end, with rays truncated at `max_range`:
/// the region any of the systems can touch.
Box rayBounds(const ScanSet& set, double max_range);

/// Reads the scans of `dir` (io::ScanFolder: *.pcd in the sensor frame, KITTI poses.txt),
/// the first `max_scans` (all if 0). Throws std::runtime_error with a one-line message naming
/// the file on any problem.
ScanSet loadScanDirectory(const std::string& dir, int max_scans);

}  // namespace ndtom::bench
