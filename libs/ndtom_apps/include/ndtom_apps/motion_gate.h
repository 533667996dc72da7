// The paper's insertion rule (Sec. IV-B-2: "adding scans every 0.05 m of distance travelled"):
// a scan is kept only when the sensor moved or turned enough since the last kept scan.
#pragma once

#include <Eigen/Geometry>
#include <optional>

namespace ndtom::apps {

struct MotionThresholds {
  double min_travel = 0;    ///< m; 0 together with min_turn = 0: every scan is kept
  double min_turn_deg = 0;  ///< degrees (angle of the relative rotation)
  bool enabled() const { return min_travel > 0 || min_turn_deg > 0; }
};

class MotionGate {
 public:
  explicit MotionGate(const MotionThresholds& t) : t_(t) {}
  /// True for the first scan and for every scan whose sensor pose is at least min_travel
  /// from, or turned at least min_turn_deg against, the last accepted one (then remembered).
  /// A threshold of 0 is not used (with both 0, every scan is accepted).
  bool accept(const Eigen::Isometry3d& sensor_pose);

 private:
  MotionThresholds t_;
  std::optional<Eigen::Isometry3d> last_;
};

/// Angle of the rotation between two poses, in degrees.
double turnDegrees(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b);

}  // namespace ndtom::apps
