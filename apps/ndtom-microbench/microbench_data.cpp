#include "microbench_data.h"

#include <cmath>
#include <cstdlib>
#include <random>
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

std::vector<Eigen::Isometry3d> particlesAround(const Eigen::Isometry3d& truth) {
  using Eigen::AngleAxisd, Eigen::Vector3d;
  std::mt19937 rng(11);
  std::normal_distribution<double> g(0.0, 1.0);
  const double deg = M_PI / 180;
  std::vector<Eigen::Isometry3d> particles;
  for (int i = 0; i < 1000; ++i) {
    Eigen::Isometry3d move = Eigen::Isometry3d::Identity();
    move.linear() = (AngleAxisd(3 * deg * g(rng), Vector3d::UnitZ()) *
                     AngleAxisd(1 * deg * g(rng), Vector3d::UnitY()) *
                     AngleAxisd(1 * deg * g(rng), Vector3d::UnitX()))
                        .toRotationMatrix();
    move.translation() = Vector3d(0.2 * g(rng), 0.2 * g(rng), 0.05 * g(rng));
    particles.push_back(move * truth);
  }
  return particles;
}

}  // namespace ndtom::microbench
