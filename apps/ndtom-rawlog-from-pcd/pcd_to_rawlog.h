// A folder of posed lidar scans as the inputs of MRPT's pf-localization: the rawlog (each
// scan a sensory frame with one CObservationPointCloud, preceded by the odometry increment
// from the previous scan), the reference poses as its ground-truth file, and optionally a
// simplemap of other scans at their poses to build the map from.
#pragma once

#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationPointCloud.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <random>
#include <string>
#include <vector>

#include "ndtom_apps/progress.h"
#include "rawlog_options.h"

namespace ndtom::rawlog {

/// A point cloud observation of `points` (sensor frame, float as MRPT stores them; non-finite
/// points dropped) labelled "LIDAR", at time `time` (s), the sensor at the robot's origin.
mrpt::obs::CObservationPointCloud::Ptr pointCloudObservation(
    const std::vector<Eigen::Vector3d>& points, double time);

/// Odometry for the pose change `increment`: its (x, y, z, yaw, pitch, roll) plus Gaussian
/// noise drawn from `rng` as `noise` says, with that noise as the covariance.
mrpt::obs::CActionRobotMovement3D odometryAction(const mrpt::poses::CPose3D& increment,
                                                 const OdometryNoise& noise, std::mt19937_64& rng,
                                                 double time);

struct ConversionReport {
  size_t log_scans = 0, map_scans = 0;
  size_t log_points = 0, map_points = 0;
  std::vector<std::string> files;  ///< written, final names
};

/// Reads the folder and writes the outputs under temporary names, renamed into place
/// together at the end. Throws apps::UsageError / apps::InputError on bad input.
ConversionReport convertFolder(const RawlogOptions& options, apps::Progress& progress);

}  // namespace ndtom::rawlog
