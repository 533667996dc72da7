#include "ndtom_apps/trajectory_poses.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ndtom_apps/scan_source.h"

namespace ndtom::apps {

TrajectoryPoses::TrajectoryPoses(const std::string& path, ndtom::io::PoseFormat format,
                                 double time_tolerance)
    : path_(path), tolerance_(time_tolerance) {
  ndtom::io::PoseFormat used = format;
  try {
    poses_ = ndtom::io::readPoseFile(path, format, &used);
  } catch (const std::exception& e) {
    throw InputError(e.what());
  }
  by_time_ = used == ndtom::io::PoseFormat::Tum;
  if (by_time_)
    std::stable_sort(poses_.begin(), poses_.end(),
                     [](const auto& a, const auto& b) { return a.time < b.time; });
}

long TrajectoryPoses::nearest(double time) const {
  const auto after = std::lower_bound(poses_.begin(), poses_.end(), time,
                                      [](const auto& p, double t) { return p.time < t; });
  long best = -1;
  double best_gap = tolerance_;
  for (auto it : {after - (after != poses_.begin() ? 1 : 0), after}) {
    if (it == poses_.end()) continue;
    const double gap = std::abs(it->time - time);
    if (gap <= best_gap) {
      best_gap = gap;
      best = long(it - poses_.begin());
    }
  }
  return best;
}

void TrajectoryPoses::checkCovers(const std::vector<double>& scan_times,
                                  const std::string& scans) const {
  if (!by_time_) {
    if (poses_.size() != scan_times.size())
      throw InputError(path_ + ": " + std::to_string(poses_.size()) + " poses for " +
                       std::to_string(scan_times.size()) + " scans in " + scans +
                       " (KITTI format: line i is the pose of the i-th scan)");
    return;
  }
  size_t missing = 0;
  double first_missing = 0;
  for (const double t : scan_times)
    if (nearest(t) < 0 && missing++ == 0) first_missing = t;
  if (missing > 0) {
    std::ostringstream msg;
    msg.precision(16);
    msg << path_ << ": no pose within " << tolerance_ << " s of " << missing << " of the "
        << scan_times.size() << " scans in " << scans << " (first at t = " << first_missing
        << " s; see --pose-time-tolerance)";
    throw InputError(msg.str());
  }
}

Eigen::Isometry3d TrajectoryPoses::poseFor(size_t index, double time) const {
  if (!by_time_) return poses_.at(index).pose;
  const long i = nearest(time);
  if (i < 0) throw InputError(path_ + ": no pose for a scan (checkCovers not called)");
  return poses_[size_t(i)].pose;
}

}  // namespace ndtom::apps
