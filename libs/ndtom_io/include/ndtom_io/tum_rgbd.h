// TUM RGB-D sequences (Sturm et al., IROS 2012): depth PNGs with camera poses.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace ndtom::io {

class TumError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Pinhole intrinsics of the depth image and its scale. Defaults: TUM's values for
/// registered depth (fx = fy = 525, cx = 319.5, cy = 239.5) and 5000 units per metre.
struct DepthCamera {
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
  double depth_scale = 5000.0;
  void validate() const;  ///< throws std::invalid_argument naming the bad value
};

struct TumFrame {
  double time = 0;
  std::string depth_path;
  Eigen::Isometry3d camera_to_world = Eigen::Isometry3d::Identity();  ///< optical frame
};

struct TumSequence {
  std::vector<TumFrame> frames;
  size_t frames_without_pose = 0;  ///< depth images with no ground truth within 20 ms
};

/// Reads a sequence folder. Accepted layouts, tried in this order:
///  - associations.txt with "rgb-file depth-file tx ty tz qx qy qz qw" per line;
///  - associations.txt from TUM's associate.py ("t rgb-file t depth-file") + groundtruth.txt;
///  - depth.txt ("t depth-file") + groundtruth.txt.
/// Ground truth is matched by the nearest time stamp within 20 ms.
TumSequence readTumSequence(const std::string& folder);

/// Largest depth image read (4096 x 4096): checked from the PNG header before decoding.
inline constexpr uint64_t kMaxDepthImagePixels = uint64_t(1) << 24;

/// Back-projects every `decimation`-th pixel of a 16-bit depth PNG into the camera's optical
/// frame (x right, y down, z forward). Zero pixels (no reading) are skipped. Throws TumError
/// for a file that is not a regular file, not a 16-bit grey PNG, larger than
/// kMaxDepthImagePixels, or that could give more than `max_points` points.
std::vector<Eigen::Vector3d> readDepthImagePoints(const std::string& png_path,
                                                  const DepthCamera& camera, int decimation = 1,
                                                  uint64_t max_points = kMaxDepthImagePixels);

}  // namespace ndtom::io
