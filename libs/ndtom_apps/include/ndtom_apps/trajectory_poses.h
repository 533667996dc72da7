// A trajectory file given with --poses, matched to the scans of a log: a KITTI file line by
// line (line i is the pose of scan i), a TUM trajectory by the nearest time stamp.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "ndtom_io/pose_file.h"

namespace ndtom::apps {

class TrajectoryPoses {
 public:
  /// Reads the file; throws InputError naming it (unreadable, bad line, no poses).
  TrajectoryPoses(const std::string& path, ndtom::io::PoseFormat format, double time_tolerance);

  bool matchesByTime() const { return by_time_; }
  size_t size() const { return poses_.size(); }
  const std::string& path() const { return path_; }

  /// Throws InputError unless every scan has a pose: as many lines as scans (KITTI), or a
  /// pose within the time tolerance of every scan time (TUM). `scans` names them.
  void checkCovers(const std::vector<double>& scan_times, const std::string& scans) const;

  /// The pose of scan `index` taken at `time` (s); call checkCovers() first.
  Eigen::Isometry3d poseFor(size_t index, double time) const;

 private:
  /// Index of the pose nearest to `time`, or -1 if none is within the tolerance.
  long nearest(double time) const;

  std::string path_;
  bool by_time_ = false;
  double tolerance_;
  std::vector<ndtom::io::StampedPose> poses_;  ///< by time for TUM files
};

}  // namespace ndtom::apps
