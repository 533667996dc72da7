// Where the next scan was taken, before registration: the last pose moved again by the last
// motion (constant velocity), scaled by the ratio of the time steps when the scans are timed.
// Tracking in a prior map (ndtom-localize) and online mapping (OnlineMapper) predict so.
#pragma once

#include <Eigen/Geometry>
#include <optional>

namespace ndtom {

class ConstantVelocity {
 public:
  explicit ConstantVelocity(const Eigen::Isometry3d& initial) : last_(initial) {}

  /// The prediction for a scan at `time` (s).
  Eigen::Isometry3d predict(double time) const;
  /// The pose found for the scan at `time`.
  void update(const Eigen::Isometry3d& pose, double time);
  /// The last pose given to update() (the initial pose before that).
  const Eigen::Isometry3d& lastPose() const { return last_; }
  /// The poses now given in a frame moved by `change` (old pose p is change · p): the last
  /// pose moves, the motion between scans (relative) stays.
  void moveFrame(const Eigen::Isometry3d& change) { last_ = change * last_; }

 private:
  Eigen::Isometry3d last_;
  std::optional<double> last_time_;
  Eigen::Isometry3d motion_ = Eigen::Isometry3d::Identity();  ///< last⁻¹ of the one before · last
  double motion_seconds_ = 0;                                 ///< its time step; 0: unknown
};

/// `motion` scaled by `factor` along its screw (SE(3)'s exp(factor · log(motion))): factor 2
/// is the motion done twice, 0.5 half of it.
Eigen::Isometry3d scaledMotion(const Eigen::Isometry3d& motion, double factor);

}  // namespace ndtom
