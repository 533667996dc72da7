// Absolute trajectory error (Sturm et al. 2012): positions of an estimated trajectory against
// a reference, pose i against pose i, after the rigid motion that best aligns the two
// (Umeyama 1991, no scale). An odometry starts in its own frame; the alignment removes that
// choice, not the drift.
#pragma once

#include <Eigen/Geometry>
#include <vector>

namespace ndtom {

struct TrajectoryError {
  size_t poses = 0;
  double rmse = 0, max = 0;  ///< m, after alignment
  double final = 0;          ///< m, of the last pose after alignment
  double length = 0;         ///< of the reference path (m)
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();  ///< estimate -> reference
};

/// Throws std::invalid_argument if the lists differ in length or hold fewer than 3 positions.
TrajectoryError alignedTrajectoryError(const std::vector<Eigen::Vector3d>& estimate,
                                       const std::vector<Eigen::Vector3d>& reference);

}  // namespace ndtom
