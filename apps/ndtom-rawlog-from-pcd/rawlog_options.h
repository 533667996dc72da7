// The command line of ndtom-rawlog-from-pcd.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

namespace ndtom::rawlog {

/// Scans first..last of a folder, both included, counted from 0 in the folder's order.
struct ScanRange {
  size_t first = 0, last = 0;
  bool contains(size_t i) const { return i >= first && i <= last; }
};

/// How the odometry of the rawlog differs from the poses: each increment (x, y, z, yaw,
/// pitch, roll) gets independent Gaussian noise of these standard deviations, and the action
/// declares the same as its covariance, so the filter's motion model is the true one.
struct OdometryNoise {
  double std_xyz = 0.05;  ///< (m)
  double std_deg = 1.0;   ///< (degrees)
  uint64_t seed = 1;
};

struct RawlogOptions {
  std::string folder;  ///< *.pcd in the sensor frame + poses.txt (KITTI) [+ times.txt]
  std::string prefix;  ///< PREFIX.rawlog, PREFIX.gt.txt [, PREFIX.simplemap]
  std::optional<ScanRange> log_scans;  ///< the rawlog's scans (default: all)
  std::optional<ScanRange> map_scans;  ///< the simplemap's scans (default: no simplemap)
  uint32_t decimation = 1;             ///< 1 point in N of each scan
  OdometryNoise noise;
  bool quiet = false;
  bool help = false;
};

/// Throws apps::UsageError with a one-line message for unknown options, missing or bad values.
RawlogOptions parseRawlogOptions(int argc, char** argv);
std::string helpText();

/// "A:B" (A <= B) as a range; throws apps::UsageError naming `option`.
ScanRange parseScanRange(const std::string& option, const std::string& text);

}  // namespace ndtom::rawlog
