// Trajectory files: KITTI odometry poses (3x4 row-major [R|t] per line) and the TUM
// trajectory format ("timestamp tx ty tz qx qy qz qw" per line).
#pragma once

#include <Eigen/Geometry>
#include <stdexcept>
#include <string>
#include <vector>

namespace ndtom::io {

class PoseFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class PoseFormat { Auto, Kitti, Tum };

struct StampedPose {
  double time = 0;  ///< seconds; the line number for KITTI files, which carry no time
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  ///< sensor -> world
};

/// Reads every pose; Auto takes KITTI if the first data line has 12 numbers and TUM for 8, and
/// every line must then have that format. Lines starting with '#' and blank lines are
/// skipped. `used`, if given, receives the format read. Throws PoseFileError naming the file
/// and line (also for a KITTI rotation with determinant -1, or a file that is not a regular
/// file of at most 256 MiB).
std::vector<StampedPose> readPoseFile(const std::string& path, PoseFormat format = PoseFormat::Auto,
                                      PoseFormat* used = nullptr);

/// The poses as KITTI lines (row-major [R|t], 12 numbers) printed with %.17g: readPoseFile
/// gets every translation back bit for bit, and every rotation to its last bits (it
/// re-orthonormalises).
std::string kittiPoseText(const std::vector<Eigen::Isometry3d>& poses);
/// Writes kittiPoseText(poses) to `path` atomically (the old file stays on failure); throws
/// PoseFileError naming the file.
void writeKittiPoseFile(const std::string& path, const std::vector<Eigen::Isometry3d>& poses);

/// Pose from translation and quaternion (x, y, z, w as TUM writes them); rejects a zero
/// or non-finite quaternion with std::invalid_argument.
Eigen::Isometry3d poseFromTranslationQuaternion(const double t[3], double qx, double qy, double qz,
                                                double qw);

}  // namespace ndtom::io
