#include "clouds.h"

#include <filesystem>
#include <stdexcept>

#include "ndtom_io/scan_folder.h"
#include "ndtom_io/tum_rgbd.h"

namespace ndtom::eval {

namespace {

// The finite points, in the world frame.
Cloud transformed(std::string name, std::vector<Eigen::Vector3d> sensor_points,
                  const Eigen::Isometry3d& sensor_to_world) {
  io::PointFilter finite;
  finite.drop_non_finite = true;
  io::filterPoints(sensor_points, finite);
  Cloud cloud;
  cloud.name = std::move(name);
  cloud.origin = sensor_to_world.translation();
  cloud.points.reserve(sensor_points.size());
  for (const Eigen::Vector3d& p : sensor_points) cloud.points.push_back(sensor_to_world * p);
  return cloud;
}

// The programs read the layout scripts/fetch-data.sh writes: say so when a folder is missing.
void requireFolder(const std::string& folder, const std::string& what) {
  if (!std::filesystem::is_directory(folder))
    throw std::runtime_error(what + " folder " + folder +
                             " not found: run scripts/fetch-data.sh to download it (or pass its "
                             "path, see --help)");
}

size_t howMany(size_t available, int wanted) {
  return wanted > 0 ? std::min(available, size_t(wanted)) : available;
}

}  // namespace

std::vector<Cloud> loadTumClouds(const std::string& folder, int max_frames, int decimation) {
  requireFolder(folder, "TUM");
  const io::TumSequence sequence = io::readTumSequence(folder);
  if (sequence.frames.empty()) throw std::runtime_error("TUM sequence " + folder + ": no frames");
  const io::DepthCamera camera;  // TUM's default intrinsics for registered depth
  std::vector<Cloud> clouds;
  for (size_t i = 0; i < howMany(sequence.frames.size(), max_frames); ++i) {
    const io::TumFrame& f = sequence.frames[i];
    clouds.push_back(transformed(f.depth_path,
                                 io::readDepthImagePoints(f.depth_path, camera, decimation),
                                 f.camera_to_world));
  }
  return clouds;
}

std::vector<Cloud> loadLidarClouds(const std::string& folder, int max_scans,
                                   const apps::MotionThresholds& motion, size_t* available) {
  requireFolder(folder, "lidar");
  const io::ScanFolder scans(folder);
  std::vector<Cloud> clouds;
  apps::MotionGate gate(motion);
  const size_t n = howMany(scans.size(), max_scans);
  if (available) *available = n;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Isometry3d& pose = scans.poses()[i].pose;
    if (!gate.accept(pose)) continue;
    clouds.push_back(transformed(scans.path(i), scans.read(i).points, pose));
  }
  return clouds;
}

size_t totalPoints(const std::vector<Cloud>& clouds) {
  size_t n = 0;
  for (const Cloud& c : clouds) n += c.points.size();
  return n;
}

}  // namespace ndtom::eval
