// Keyframes of an online run: every few metres or degrees of turn a new one starts; it holds
// the NDT-OM of its own scans (exact RCU, in the odometry's frame) and its first scan, which
// loop closure registers against other keyframes' submaps. A pose graph has one node a
// keyframe; each scan's pose is its keyframe's times a fixed offset.
#pragma once

#include <Eigen/Geometry>
#include <cstddef>
#include <vector>

#include "ndtom/map/ndt_map.h"

namespace ndtom {

struct KeyframeOptions {
  /// A scan starts a new keyframe once the sensor moved this far (m) or turned this much
  /// (degrees) from the current keyframe's first scan (Default: 10 m, 30°).
  double distance = 10;
  double turn_deg = 30;
};

/// Throws std::invalid_argument("<option> = <value>: <why>") on the first bad value.
void validate(const KeyframeOptions& options);

/// Whether a scan at `pose` starts a new keyframe after the one anchored at `anchor`.
bool startsKeyframe(const KeyframeOptions& options, const Eigen::Isometry3d& anchor,
                    const Eigen::Isometry3d& pose);

struct Keyframe {
  explicit Keyframe(const MapOptions& map) : submap(map) {}
  size_t first_scan = 0;
  Eigen::Isometry3d anchor = Eigen::Isometry3d::Identity();  ///< first scan, odometry frame
  double path_length = 0;  ///< odometry path from the run's first scan to the anchor (m)
  std::vector<Eigen::Vector3d> anchor_scan;  ///< the first scan, sensor frame
  NdtMap submap;                             ///< its scans, odometry frame
  size_t scans = 0;                          ///< inserted into the submap
  /// Odometry placed all its scans by tracking. A scan recovered by a search or lost may sit
  /// off the others (city: the run's second scan, recovered 1.1 m off its first), so the
  /// anchor may not fit the submap: such a keyframe anchors no loop.
  bool consistent = true;
};

}  // namespace ndtom
