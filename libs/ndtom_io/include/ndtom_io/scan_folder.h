// A folder of lidar scans with their poses, the layout of the data the project ships
// (tests/data/balm-realworld): the scans as .pcd files (points in the sensor frame) taken in
// natural order (full0.pcd, full1.pcd, ..., full10.pcd), and a pose file whose line i is the
// pose of the i-th scan (by default FOLDER/poses.txt, KITTI: [R|t], sensor -> world).
// Points come as the files hold them; what a program drops is its PointFilter.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::io {

class ScanFolderError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Which points of a scan a program keeps; by default all of them.
struct PointFilter {
  uint32_t decimation = 1;       ///< 1 point in N, by position in the file (0 or 1: all)
  bool drop_non_finite = false;  ///< NaN or infinite coordinates (rows without a return)
  bool drop_origin = false;      ///< exactly (0, 0, 0), which some drivers write for no return
};

/// What a filter dropped, by reason.
struct DroppedPoints {
  size_t decimated = 0;
  size_t invalid = 0;  ///< non-finite or at the origin
};

/// Keeps, in order and in place, the points `filter` keeps: first every N-th of the file's,
/// then of those the valid ones.
DroppedPoints filterPoints(std::vector<Eigen::Vector3d>& points, const PointFilter& filter);

struct ScanFolderOptions {
  std::string poses_file;                      ///< empty: FOLDER/poses.txt
  PoseFormat pose_format = PoseFormat::Kitti;  ///< Auto: KITTI or TUM, by the first line
  /// Without it, a folder with no pose file is an error; with it, its scans have no poses
  /// (hasPoses() false). A pose file named in `poses_file` must exist either way.
  bool poses_required = true;
  /// False: the pose file is not read even if there is one (scans mapped without poses).
  bool read_poses = true;
};

class ScanFolder {
 public:
  /// Lists the folder's .pcd files and reads the pose file. Throws ScanFolderError naming the
  /// folder or file (not a folder, no .pcd file, no pose file, not one pose per scan), or
  /// PoseFileError for an unreadable pose file.
  explicit ScanFolder(const std::string& folder, const ScanFolderOptions& options = {});

  size_t size() const { return files_.size(); }
  const std::string& folder() const { return folder_; }
  /// The i-th scan's file name ("full3.pcd") and path.
  const std::string& fileName(size_t i) const { return files_.at(i); }
  std::string path(size_t i) const;

  bool hasPoses() const { return !poses_.empty(); }
  /// The pose file read, or looked for when there is none.
  const std::string& posesPath() const { return poses_path_; }
  /// One per scan (sensor -> world; the time is the line number for KITTI), or none.
  const std::vector<StampedPose>& poses() const { return poses_; }

  /// The i-th scan in its sensor frame, the points `filter` keeps; `dropped`, if given, gets
  /// what it dropped. Throws PcdError naming the file (also for more than `max_points`).
  PointCloud read(size_t i, const PointFilter& filter = {}, DroppedPoints* dropped = nullptr,
                  uint64_t max_points = kDefaultMaxPcdPoints) const;

 private:
  std::string folder_;
  std::vector<std::string> files_;  ///< natural order
  std::string poses_path_;
  std::vector<StampedPose> poses_;
};

}  // namespace ndtom::io
