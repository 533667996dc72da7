#include "lidar_sequence.h"

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "ndtom_io/scan_folder.h"

namespace ndtom::regbench {

namespace fs = std::filesystem;

size_t LidarSequence::totalPoints() const {
  size_t n = 0;
  for (const auto& scan : scans) n += scan.size();
  return n;
}

LidarSequence loadLidarSequence(const std::string& dir) {
  if (!fs::is_directory(dir)) throw std::runtime_error("--dataset " + dir + ": not a directory");
  const io::ScanFolder folder(dir);
  LidarSequence sequence;
  for (const io::StampedPose& p : folder.poses()) sequence.poses.push_back(p.pose);
  fs::path name = fs::path(dir).lexically_normal();
  if (name.filename().empty()) name = name.parent_path();  // "dir/" names "dir"
  sequence.name = name.filename().string();

  // NaN rows and zero rows (no return) are dropped for every system alike, and counted.
  io::PointFilter no_returns;
  no_returns.drop_non_finite = no_returns.drop_origin = true;
  for (size_t i = 0; i < folder.size(); ++i) {
    io::DroppedPoints dropped;
    sequence.scans.push_back(folder.read(i, no_returns, &dropped).points);
    sequence.dropped_points += dropped.invalid;
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
