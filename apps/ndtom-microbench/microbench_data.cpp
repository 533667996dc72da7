#include "microbench_data.h"

#include <cstdlib>
#include <string>

#include "ndtom_io/pcd_reader.h"
#include "ndtom_io/pose_file.h"

namespace ndtom::microbench {

const std::vector<WorldScan>& realScans(size_t count) {
  static std::vector<WorldScan> scans;
  if (scans.size() >= count) return scans;
  const char* env = std::getenv("NDTOM_MICROBENCH_DATA");
  const std::string dir = env && *env ? env : NDTOM_MICROBENCH_DATA;
  const auto poses = io::readPoseFile(dir + "/poses.txt", io::PoseFormat::Kitti);
  for (size_t i = scans.size(); i < count && i < poses.size(); ++i) {
    const io::PointCloud cloud = io::readPcd(dir + "/full" + std::to_string(i) + ".pcd");
    WorldScan scan{poses[i].pose.translation(), {}, poses[i].pose};
    for (const Eigen::Vector3d& p : cloud.points)
      if (p.allFinite() && !p.isZero(0.0)) scan.points.push_back(poses[i].pose * p);
    scans.push_back(std::move(scan));
  }
  return scans;
}

MapOptions benchOptions(double resolution, RayMode mode) {
  MapOptions o;
  o.resolution = resolution;
  o.scan.max_range = 30.0;
  o.scan.ray_mode = mode;
  return o;
}

}  // namespace ndtom::microbench
