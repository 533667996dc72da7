// A drive through the procedural city written as ndtom-localize reads it, for tests that
// localize one drive in the map of another.
#pragma once

#include <Eigen/Geometry>
#include <cstdio>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include "city_route.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"
#include "simulated_lidar.h"

namespace city_drive {

// The ground (z = 0) would lie on a cell boundary, where grazing rays clear the cells that
// hold its points: the world is raised by half a cell, as any real ground is off the grid.
inline const Eigen::Translation3d kRaise(0, 0, 0.2);

/// scan000000.pcd ... (sensor frame), times.txt (2 Hz) and poses.txt (the reference, raised).
inline void writeDrive(const ndtom::world::CityWorld& city, const ndtom::world::LidarModel& lidar,
                       const std::vector<Eigen::Isometry3d>& poses,
                       const std::filesystem::path& folder) {
  std::filesystem::create_directories(folder);
  std::ofstream times(folder / "times.txt");
  std::vector<Eigen::Isometry3d> raised;
  for (size_t i = 0; i < poses.size(); ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "scan%06zu.pcd", i);
    ndtom::io::writePcdBinary((folder / name).string(),
                              ndtom::world::simulateScan(city, lidar, poses[i], i));
    raised.push_back(kRaise * poses[i]);
    times << 0.5 * double(i) << "\n";
  }
  ndtom::io::writeKittiPoseFile((folder / "poses.txt").string(), raised);
}

/// The scans of `poses` (raised) inserted into `map`, those `keep` accepts (by index).
inline void insertDrive(ndtom::NdtMap& map, const ndtom::world::CityWorld& city,
                        const ndtom::world::LidarModel& lidar,
                        const std::vector<Eigen::Isometry3d>& poses,
                        const std::function<bool(size_t)>& keep = {}) {
  for (size_t i = 0; i < poses.size(); ++i) {
    if (keep && !keep(i)) continue;
    auto points = ndtom::world::simulateScan(city, lidar, poses[i], i);
    for (auto& p : points) p = kRaise * (poses[i] * p);
    map.insertScan(points, kRaise * poses[i].translation());
  }
}

/// `pose` raised, as ndtom-localize's --initial reads it: "x y z qx qy qz qw".
inline std::string initialPose(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = kRaise * pose.translation();
  std::ostringstream out;
  out << std::setprecision(12) << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " "
      << q.y() << " " << q.z() << " " << q.w();
  return out.str();
}

}  // namespace city_drive
