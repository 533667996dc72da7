#include "microbench_data.h"

#include <cstdlib>
#include <string>

#include "ndtom_io/scan_folder.h"

namespace ndtom::microbench {

const std::vector<WorldScan>& realScans(size_t count) {
  static std::vector<WorldScan> scans;
  if (scans.size() >= count) return scans;
  const char* env = std::getenv("NDTOM_MICROBENCH_DATA");
  const std::string dir = env && *env ? env : NDTOM_MICROBENCH_DATA;
  const io::ScanFolder folder(dir);
  io::PointFilter no_returns;  // as the benchmarks of whole systems (ndtom-bench) drop them
  no_returns.drop_non_finite = no_returns.drop_origin = true;
  for (size_t i = scans.size(); i < count && i < folder.size(); ++i) {
    const Eigen::Isometry3d& pose = folder.poses()[i].pose;
    WorldScan scan{pose.translation(), {}, pose};
    for (const Eigen::Vector3d& p : folder.read(i, no_returns).points)
      scan.points.push_back(pose * p);
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
