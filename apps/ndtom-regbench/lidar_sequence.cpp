#include "lidar_sequence.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::regbench {

namespace fs = std::filesystem;

size_t LidarSequence::totalPoints() const {
  size_t n = 0;
  for (const auto& scan : scans) n += scan.size();
  return n;
}

LidarSequence loadLidarSequence(const std::string& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error("--dataset " + dir + ": not a directory");
  LidarSequence sequence;
  for (const io::StampedPose& p :
       io::readPoseFile((fs::path(dir) / "poses.txt").string(), io::PoseFormat::Kitti))
    sequence.poses.push_back(p.pose);
  if (sequence.poses.empty()) throw std::runtime_error("--dataset " + dir + ": no pose listed");
  fs::path folder = fs::path(dir).lexically_normal();
  if (folder.filename().empty()) folder = folder.parent_path();  // "dir/" names "dir"
  sequence.name = folder.filename().string();

  for (size_t i = 0; i < sequence.poses.size(); ++i) {
    io::PointCloud cloud =
        io::readPcd((fs::path(dir) / ("full" + std::to_string(i) + ".pcd")).string());
    // NaN rows and zero rows (no return) are dropped for every system alike, and counted.
    auto& points = cloud.points;
    const auto kept = std::remove_if(points.begin(), points.end(), [](const Eigen::Vector3d& p) {
      return !p.allFinite() || p.isZero(0.0);
    });
    sequence.dropped_points += size_t(points.end() - kept);
    points.erase(kept, points.end());
    sequence.scans.push_back(std::move(points));
  }
  return sequence;
}

MapScans mapScans(const LidarSequence& sequence, const std::vector<int>& held_out,
                  double max_range) {
  for (int scan : held_out)
    if (scan < 0 || size_t(scan) >= sequence.scans.size())
      throw std::runtime_error("--held-out " + std::to_string(scan) + ": the dataset has scans 0-" +
                               std::to_string(sequence.scans.size() - 1));
  MapScans map;
  for (size_t i = 0; i < sequence.scans.size(); ++i) {
    if (std::count(held_out.begin(), held_out.end(), int(i))) continue;
    map.scans.push_back(int(i));
    for (const Eigen::Vector3d& p : sequence.scans[i])
      if (p.norm() <= max_range) map.near_points.push_back(sequence.poses[i] * p);
  }
  if (map.scans.empty()) throw std::runtime_error("--held-out: no scan is left for the map");
  return map;
}

}  // namespace ndtom::regbench
