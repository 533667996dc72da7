// The real lidar scans shipped in tests/data/balm-realworld, in the world frame.
#pragma once

#include <string>
#include <vector>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::testing {

struct WorldScan {
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d origin;
};

/// The first `count` scans (of 10), moved by their poses.
inline std::vector<WorldScan> lidarScansInWorld(size_t count) {
  const std::string dir = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld/";
  const auto poses = io::readPoseFile(dir + "poses.txt");
  std::vector<WorldScan> scans;
  for (size_t i = 0; i < count && i < poses.size(); ++i) {
    auto cloud = io::readPcd(dir + "full" + std::to_string(i) + ".pcd");
    for (auto& p : cloud.points) p = poses[i].pose * p;
    scans.push_back({std::move(cloud.points), poses[i].pose.translation()});
  }
  return scans;
}

}  // namespace ndtom::testing
