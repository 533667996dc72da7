// The BALM real-world lidar scans shipped with the tests (tests/data/balm-realworld), as MRPT
// objects for the plugin's tests: each scan as a points map, the poses as CPose3D.
#pragma once

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::testing {

inline const std::string kBalm = std::string(NDTOM_TEST_DATA_DIR) + "/balm-realworld";

inline mrpt::poses::CPose3D toPose(const Eigen::Isometry3d& t) {
  mrpt::math::CMatrixDouble44 m;
  m.asEigen() = t.matrix();
  return mrpt::poses::CPose3D(m);
}

inline Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose) {
  Eigen::Isometry3d t;
  t.matrix() = pose.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  return t;
}

/// Scan `i` in its sensor frame, without non-finite points and those within 0.5 m of the
/// sensor (the scanning platform).
inline mrpt::maps::CSimplePointsMap::Ptr balmScan(int i) {
  const auto cloud = ndtom::io::readPcd(kBalm + "/full" + std::to_string(i) + ".pcd");
  auto points = mrpt::maps::CSimplePointsMap::Create();
  for (const auto& p : cloud.points)
    if (p.allFinite() && p.norm() > 0.5) points->insertPoint(p.x(), p.y(), p.z());
  return points;
}

/// The scans' poses (sensor -> world, KITTI's poses.txt), in scan order.
inline std::vector<mrpt::poses::CPose3D> balmPoses() {
  std::vector<mrpt::poses::CPose3D> poses;
  for (const auto& p : ndtom::io::readPoseFile(kBalm + "/poses.txt"))
    poses.push_back(toPose(p.pose));
  return poses;
}

}  // namespace ndtom::testing
