#include "ndtom_apps/motion_gate.h"

#include <algorithm>
#include <cmath>

namespace ndtom::apps {

double turnDegrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  const Eigen::Matrix3d r = a.linear().transpose() * b.linear();
  // acos of (trace - 1) / 2, clamped: rounding can push it just outside [-1, 1].
  const double c = std::clamp((r.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c) * 180.0 / M_PI;
}

bool MotionGate::accept(const Eigen::Isometry3d& pose) {
  const bool keep =
      !last_ || !t_.enabled() ||
      (t_.min_travel > 0 && (pose.translation() - last_->translation()).norm() >= t_.min_travel) ||
      (t_.min_turn_deg > 0 && turnDegrees(*last_, pose) >= t_.min_turn_deg);
  if (keep) last_ = pose;
  return keep;
}

}  // namespace ndtom::apps
