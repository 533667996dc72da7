#include "ndtom/localization/motion_prediction.h"

#include <algorithm>
#include <cmath>

namespace ndtom {

namespace {

// V(ω) of SE(3)'s exponential: t = V·u for the twist (u, ω).
Eigen::Matrix3d leftJacobian(const Eigen::Vector3d& omega) {
  const double theta = omega.norm();
  Eigen::Matrix3d w;
  w << 0, -omega.z(), omega.y(), omega.z(), 0, -omega.x(), -omega.y(), omega.x(), 0;
  if (theta < 1e-9) return Eigen::Matrix3d::Identity() + 0.5 * w;
  return Eigen::Matrix3d::Identity() + (1 - std::cos(theta)) / (theta * theta) * w +
         (theta - std::sin(theta)) / (theta * theta * theta) * w * w;
}

}  // namespace

Eigen::Isometry3d scaledMotion(const Eigen::Isometry3d& motion, double factor) {
  const Eigen::AngleAxisd rotation(motion.linear());
  const Eigen::Vector3d omega = rotation.angle() * rotation.axis();
  const Eigen::Vector3d u = leftJacobian(omega).inverse() * motion.translation();  // log
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();                             // exp
  out.linear() = Eigen::AngleAxisd(rotation.angle() * factor, rotation.axis()).toRotationMatrix();
  out.translation() = leftJacobian(factor * omega) * (factor * u);
  return out;
}

Eigen::Isometry3d ConstantVelocity::predict(double time) const {
  if (!last_time_) return last_;
  double factor = 1;
  const double dt = time - *last_time_;
  // Timed scans: the same velocity over the new step, bounded so that a gap in the log does
  // not throw the prediction far away.
  if (motion_seconds_ > 0 && dt > 0) factor = std::min(dt / motion_seconds_, 3.0);
  return last_ * scaledMotion(motion_, factor);
}

void ConstantVelocity::update(const Eigen::Isometry3d& pose, double time) {
  if (last_time_) {
    motion_ = last_.inverse() * pose;
    motion_seconds_ = time > *last_time_ ? time - *last_time_ : 0;
  }
  last_ = pose;
  last_time_ = time;
}

}  // namespace ndtom
