#include "scan_set.h"

#include <Eigen/Geometry>
#include <filesystem>
#include <stdexcept>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::bench {

size_t ScanSet::totalPoints() const {
  size_t n = 0;
  for (const Scan& s : scans) n += s.points.size();
  return n;
}

Box rayBounds(const ScanSet& set, double max_range) {
  Box box;
  for (const Scan& scan : set.scans) {
    box.extend(scan.origin);
    for (const Eigen::Vector3d& p : scan.points) {
      const Eigen::Vector3d ray = p - scan.origin;
      const double range = ray.norm();
      box.extend(range <= max_range ? p : Eigen::Vector3d(scan.origin + ray * (max_range / range)));
    }
  }
  return box;
}

ScanSet loadScanDirectory(const std::string& dir, int max_scans) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(dir))
    throw std::runtime_error("dataset " + dir +
                             ": not a directory (scripts/fetch-data.sh downloads the lidar scans)");
  const std::vector<io::StampedPose> poses =
      io::readPoseFile((fs::path(dir) / "poses.txt").string(), io::PoseFormat::Kitti);
  size_t count = poses.size();
  if (max_scans > 0) {
    if (size_t(max_scans) > poses.size())
      throw std::runtime_error("dataset " + dir + ": --scans " + std::to_string(max_scans) +
                               " but poses.txt lists " + std::to_string(poses.size()));
    count = size_t(max_scans);
  }
  if (count == 0) throw std::runtime_error("dataset " + dir + ": poses.txt lists no scan");

  ScanSet set;
  fs::path normal = fs::path(dir).lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();  // "dir/" names "dir"
  set.name = normal.filename().string();
  for (size_t i = 0; i < count; ++i) {
    const std::string file = (fs::path(dir) / ("full" + std::to_string(i) + ".pcd")).string();
    const io::PointCloud cloud = io::readPcd(file);
    Scan scan;
    scan.origin = poses[i].pose.translation();
    scan.points.reserve(cloud.points.size());
    for (const Eigen::Vector3d& p : cloud.points) {
      // NaN rows and zero rows (no return) would be rejected by some systems and crash
      // others: drop them for everyone, and count them.
      if (!p.allFinite() || p.isZero(0.0)) {
        ++set.dropped_points;
        continue;
      }
      scan.points.push_back(poses[i].pose * p);
    }
    set.scans.push_back(std::move(scan));
  }
  return set;
}

}  // namespace ndtom::bench
