// A spinning multi-beam lidar in a CityWorld: rings at evenly spaced elevations, evenly
// spaced azimuths, the range to the first surface plus Gaussian noise; rays that reach
// nothing within the range give no point (the sky). Deterministic per scan index, so scans
// can be generated in any order or on any number of threads.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "city_world.h"

namespace ndtom::world {

struct LidarModel {
  int rings = 32;
  int azimuth_steps = 900;  ///< per turn
  double elevation_low_deg = -25, elevation_top_deg = 15;
  double max_range = 80;      ///< (m)
  double range_noise = 0.02;  ///< σ (m)
  uint64_t seed = 1;
};

/// The points of one scan in the sensor frame (x forward, z up), for the sensor at `pose`
/// (sensor → world). `scan_index` picks the noise.
std::vector<Eigen::Vector3d> simulateScan(const CityWorld& city, const LidarModel& lidar,
                                          const Eigen::Isometry3d& pose, uint64_t scan_index);

}  // namespace ndtom::world
