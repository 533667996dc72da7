#include "ndtom/slam/keyframes.h"

#include <cmath>

#include "support/option_error.h"

namespace ndtom {

void validate(const KeyframeOptions& o) {
  if (!(o.distance > 0 && std::isfinite(o.distance)))
    failOption("keyframe distance", o.distance, "must be finite and > 0");
  if (!(o.turn_deg > 0 && o.turn_deg <= 180))
    failOption("keyframe turn_deg", o.turn_deg, "must be in (0, 180]");
}

bool startsKeyframe(const KeyframeOptions& o, const Eigen::Isometry3d& anchor,
                    const Eigen::Isometry3d& pose) {
  const Eigen::Isometry3d motion = anchor.inverse() * pose;
  const double turn = Eigen::AngleAxisd(motion.linear()).angle() * 180 / M_PI;
  return motion.translation().norm() >= o.distance || turn >= o.turn_deg;
}

}  // namespace ndtom
