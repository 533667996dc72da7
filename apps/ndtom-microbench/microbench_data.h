// Real scans for the micro-benchmarks: the lidar subset shipped in tests/data (every 2nd
// point), or another folder of fullN.pcd + poses.txt named by $NDTOM_MICROBENCH_DATA.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "ndtom/map/ndt_map.h"

namespace ndtom::microbench {

struct WorldScan {
  Eigen::Vector3d origin;
  std::vector<Eigen::Vector3d> points;                     ///< world frame
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> world
};

/// Scans 0 .. count-1, loaded once and cached. Throws std::runtime_error on bad data.
const std::vector<WorldScan>& realScans(size_t count);

/// Map options of the benchmarks: `resolution` (m), 30 m max range as in doc/benchmarks.md.
MapOptions benchOptions(double resolution, RayMode mode);

/// 1000 poses scattered around `truth` like a localization filter's particles (0.2 m, 3° in
/// yaw, 1° in pitch and roll, 5 cm in z; fixed seed), the same for every benchmark.
std::vector<Eigen::Isometry3d> particlesAround(const Eigen::Isometry3d& truth);

}  // namespace ndtom::microbench
