// A generated scan sequence with the shape of a car-mounted 64-ring spinning lidar in a
// walled yard: ground, four walls, parked boxes (cars, containers) and pillars. Every ray
// hits something, so each scan has exactly kRings × kAzimuthSteps = 115,200 points.
#pragma once

#include "scan_set.h"

namespace ndtom::bench {

struct SyntheticLidar {
  static constexpr int kRings = 64;
  static constexpr int kAzimuthSteps = 1800;       ///< 0.2° apart
  static constexpr double kElevationTopDeg = 2.0;  ///< as a Velodyne HDL-64E
  static constexpr double kElevationLowDeg = -24.8;
  static constexpr double kHeight = 1.8;       ///< sensor above the ground (m)
  static constexpr double kRangeNoise = 0.01;  ///< σ of the range noise (m)
  static constexpr double kStep = 1.0;         ///< distance between scans (m)
};

/// `num_scans` scans along a closed loop through the yard; deterministic (fixed seed).
ScanSet generateSyntheticScans(int num_scans);

}  // namespace ndtom::bench
