#include "scan_set.h"

#include <Eigen/Geometry>
#include <filesystem>
#include <stdexcept>

#include "ndtom_io/scan_folder.h"

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
  const io::ScanFolder folder(dir);
  size_t count = folder.size();
  if (max_scans > 0) {
    if (size_t(max_scans) > count)
      throw std::runtime_error("dataset " + dir + ": --scans " + std::to_string(max_scans) +
                               " but it has " + std::to_string(count));
    count = size_t(max_scans);
  }

  ScanSet set;
  fs::path normal = fs::path(dir).lexically_normal();
  if (normal.filename().empty()) normal = normal.parent_path();  // "dir/" names "dir"
  set.name = normal.filename().string();
  // NaN rows and zero rows (no return) would be rejected by some systems and crash others:
  // drop them for everyone, and count them.
  io::PointFilter no_returns;
  no_returns.drop_non_finite = no_returns.drop_origin = true;
  for (size_t i = 0; i < count; ++i) {
    io::DroppedPoints dropped;
    const io::PointCloud cloud = folder.read(i, no_returns, &dropped);
    set.dropped_points += dropped.invalid;
    const Eigen::Isometry3d& pose = folder.poses()[i].pose;
    Scan scan;
    scan.origin = pose.translation();
    scan.pose = pose;
    scan.points.reserve(cloud.points.size());
    for (const Eigen::Vector3d& p : cloud.points) scan.points.push_back(pose * p);
    set.scans.push_back(std::move(scan));
  }
  return set;
}

}  // namespace ndtom::bench
