// How far an estimated pose is from the reference, and what counts as a success.
#pragma once

#include <Eigen/Geometry>

namespace ndtom::regbench {

/// A registration succeeds when it ends within these of the reference pose.
inline constexpr double kSuccessMeters = 0.10;
inline constexpr double kSuccessDegrees = 1.0;

struct PoseError {
  double meters = 0;   ///< distance between the sensor positions
  double degrees = 0;  ///< angle of the rotation from one orientation to the other

  bool success() const { return meters <= kSuccessMeters && degrees <= kSuccessDegrees; }
};

PoseError poseError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth);

}  // namespace ndtom::regbench
