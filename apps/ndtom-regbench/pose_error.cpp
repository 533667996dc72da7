#include "pose_error.h"

#include <cmath>

namespace ndtom::regbench {

PoseError poseError(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
  // The angle through a quaternion (atan2), exact for small angles, unlike acos of the trace.
  const Eigen::AngleAxisd turn(estimate.linear().transpose() * truth.linear());
  return {(estimate.translation() - truth.translation()).norm(), turn.angle() * 180 / M_PI};
}

}  // namespace ndtom::regbench
