// The point clouds of an experiment, in the world frame, with their sensor origins.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "ndtom_apps/motion_gate.h"

namespace ndtom::eval {

struct Cloud {
  std::string name;                                  ///< file the cloud came from (for messages)
  std::vector<Eigen::Vector3d> points;               ///< world frame, finite points only
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();  ///< sensor position, world frame
};

/// The first `max_frames` frames (0 = all) of a TUM RGB-D sequence, every `decimation`-th
/// depth pixel, TUM's default intrinsics, ground-truth camera poses. Throws on bad data.
std::vector<Cloud> loadTumClouds(const std::string& folder, int max_frames, int decimation);

/// The scans of a folder (io::ScanFolder: full0.pcd, full1.pcd, ... with a KITTI poses.txt):
/// of the first `max_scans` (0 = all), those `motion` keeps (the paper's insertion rule; by
/// default all). `available`: how many were considered. Throws on bad data, naming
/// scripts/fetch-data.sh when the folder is missing.
std::vector<Cloud> loadLidarClouds(const std::string& folder, int max_scans,
                                   const apps::MotionThresholds& motion = {},
                                   size_t* available = nullptr);

size_t totalPoints(const std::vector<Cloud>& clouds);

}  // namespace ndtom::eval
