// When a region of a map cut around a moving sensor (a registration target) is cut again:
// after the sensor moved or turned enough since the cut, or after enough scans. Cutting costs
// more than most scans' registration, and a region a few scans old still holds what the next
// scan sees.
#pragma once

#include <Eigen/Geometry>
#include <cmath>

namespace ndtom {

struct RegionRefresh {
  double distance = 2;    ///< m moved since the cut; 0: not a reason (Default: 2)
  double angle_deg = 10;  ///< degrees turned since the cut; 0: not a reason (Default: 10)
  int scans = 10;         ///< scans since the cut (Default: 10; 1: every scan)

  /// Whether a region cut at `cut_at`, `scans_since` scans ago, is due again at `now`.
  bool due(const Eigen::Isometry3d& cut_at, const Eigen::Isometry3d& now, int scans_since) const {
    if (scans_since >= scans) return true;
    if (distance > 0 && (now.translation() - cut_at.translation()).norm() >= distance) return true;
    return angle_deg > 0 &&
           Eigen::AngleAxisd(cut_at.linear().transpose() * now.linear()).angle() * 180 / M_PI >=
               angle_deg;
  }
};

}  // namespace ndtom
