// The dataset: every scan in its sensor frame with its reference pose, and the points the
// map is made of (the scans that are not held out, in the world frame).
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <vector>

namespace ndtom::regbench {

struct LidarSequence {
  std::string name;                                 ///< the folder's name, for the summary
  std::vector<Eigen::Isometry3d> poses;             ///< sensor -> world, one per scan
  std::vector<std::vector<Eigen::Vector3d>> scans;  ///< sensor frame, finite, not at the origin
  size_t dropped_points = 0;                        ///< non-finite or at the origin, for everyone

  size_t totalPoints() const;
};

/// Reads every scan of `dir` (io::ScanFolder: *.pcd in the sensor frame, KITTI poses.txt).
/// Throws std::runtime_error with a one-line message naming the file on any problem.
LidarSequence loadLidarSequence(const std::string& dir);

/// The map's input: the scans of the sequence that are not held out, and their points within
/// the max range of their sensor in the world frame (the point maps of the peers).
struct MapScans {
  std::vector<int> scans;                    ///< their numbers
  std::vector<Eigen::Vector3d> near_points;  ///< world frame
};

/// Throws std::runtime_error if a held-out scan number is not in the sequence.
MapScans mapScans(const LidarSequence& sequence, const std::vector<int>& held_out,
                  double max_range);

}  // namespace ndtom::regbench
