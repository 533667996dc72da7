// From an MRPT observation and the robot's pose to what an NDT-OM scan insertion needs:
// the points in the world frame and the sensor's origin (robot pose ⊕ sensor pose).
// Shared by the map class and by programs that read rawlogs and simplemaps.
//
// Supported: CObservation2DRangeScan, CObservation3DRangeScan (depth image unprojected with
// its intrinsics and lens distortion exactly as MRPT's unprojectInto() does, or its stored
// points), CObservationPointCloud, CObservationVelodyneScan.
// The observation is only read, so concurrent calls on one are safe; the exception is data
// stored outside the rawlog, which MRPT's load() brings in first (as all MRPT maps do).
#pragma once

#include <mrpt/obs/CObservation.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <vector>

namespace mrpt_ndtom {

struct TPointExtractionOptions {
  /// Keep one point in N of 2D scans, point clouds and Velodyne scans (Default: 1, all).
  uint32_t decimation = 1;
  /// Depth images: use every N-th row and column (Default: 1, every pixel).
  uint32_t decimation_3d_range = 1;
  /// The largest decimation .ini files and flags take: the int range of MRPT's read_int,
  /// which read them before, so that no file that loaded fails now for its size.
  static constexpr uint32_t kMaxDecimation = 2147483647;
};

struct ObservationPoints {
  std::vector<Eigen::Vector3d> points_world;                ///< (m)
  Eigen::Vector3d sensor_origin = Eigen::Vector3d::Zero();  ///< (m)
};

/// True for the observation types listed above.
bool isSupportedObservation(const mrpt::obs::CObservation& obs);

/// The observation's valid points and sensor origin, seen from `robotPose`; nullopt for an
/// unsupported type. A supported observation without valid points gives an empty list.
/// Throws std::invalid_argument if a decimation is 0.
std::optional<ObservationPoints> observationPoints(const mrpt::obs::CObservation& obs,
                                                   const mrpt::poses::CPose3D& robotPose,
                                                   const TPointExtractionOptions& options = {});

/// The same rigid transform as an Eigen isometry.
Eigen::Isometry3d toIsometry(const mrpt::poses::CPose3D& pose);

}  // namespace mrpt_ndtom
