// Reader for PCL's PCD files (v0.5-0.7): ascii, binary and binary_compressed (LZF) data,
// any field list as long as x, y and z are there. No PCL needed.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace ndtom::io {

class PcdError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct PointCloud {
  std::vector<Eigen::Vector3d> points;  ///< in the cloud's frame; NaN points are kept
  /// VIEWPOINT: the sensor's pose in the cloud's frame (identity when absent).
  Eigen::Isometry3d viewpoint = Eigen::Isometry3d::Identity();
};

/// Points a cloud may have unless the caller says otherwise (1.6 GB as Eigen vectors).
inline constexpr uint64_t kDefaultMaxPcdPoints = uint64_t(1) << 26;

/// Throws PcdError with the file name and the reason (missing field, truncated data, not a
/// regular file or over 1 GiB, more than `max_points` points, ...). Every size in the header is
/// checked before it is used, so no header makes the reader allocate more than the points.
PointCloud readPcd(const std::string& path, uint64_t max_points = kDefaultMaxPcdPoints);
/// Same, from bytes in memory; `name` is used in error messages.
PointCloud parsePcd(const std::string& bytes, const std::string& name,
                    uint64_t max_points = kDefaultMaxPcdPoints);

/// Writes a binary PCD with fields x y z (float32): used by tests and tools.
void writePcdBinary(const std::string& path, const std::vector<Eigen::Vector3d>& points);

}  // namespace ndtom::io
