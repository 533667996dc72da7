#include "mrpt_icp_system.h"

#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDF.h>
#include <mrpt/slam/CICP.h>
#include <mrpt/version.h>

#include <cmath>
#include <cstdio>

#include "voxel_filter.h"

namespace ndtom::regbench {

namespace {

std::unique_ptr<mrpt::maps::CSimplePointsMap> pointsMap(
    const std::vector<Eigen::Vector3d>& points) {
  auto map = std::make_unique<mrpt::maps::CSimplePointsMap>();
  map->reserve(points.size());
  for (const Eigen::Vector3d& p : points)
    map->insertPoint(float(p.x()), float(p.y()), float(p.z()));
  return map;
}

}  // namespace

std::string mrptVersion() {
  return MRPT_version_str;
}

MrptIcpSystem::MrptIcpSystem(const MapScans& map, const MrptIcpSettings& settings)
    : settings_(settings), map_(pointsMap(voxelCentroids(map.near_points, settings.map_leaf))) {}

MrptIcpSystem::~MrptIcpSystem() = default;

size_t MrptIcpSystem::mapPoints() const {
  return map_->size();
}

std::string MrptIcpSystem::settings() const {
  const MrptIcpSettings& s = settings_;
  char text[400];
  std::snprintf(text, sizeof text,
                "CICP::Align3D (icpClassic), map: %zu points (centroids of %g m cubes), scan: "
                "every point, decimation %u; thresholdDist %g m, thresholdAng %g deg, ALFA %g, "
                "smallestThresholdDist %g m, maxIterations %u",
                map_->size(), s.map_leaf, s.decimation, s.threshold_dist, s.threshold_ang_degrees,
                s.alfa, s.smallest_threshold_dist, s.max_iterations);
  return text;
}

void MrptIcpSystem::setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) {
  scans_.clear();
  for (const auto* scan : scans) scans_.push_back(pointsMap(*scan));
}

Attempt MrptIcpSystem::align(size_t scan, const Eigen::Isometry3d& guess) {
  mrpt::slam::CICP icp;
  icp.options.thresholdDist = settings_.threshold_dist;
  icp.options.thresholdAng = settings_.threshold_ang_degrees * M_PI / 180;
  icp.options.ALFA = settings_.alfa;
  icp.options.smallestThresholdDist = settings_.smallest_threshold_dist;
  icp.options.maxIterations = settings_.max_iterations;
  icp.options.corresponding_points_decimation = settings_.decimation;
  icp.options.skip_cov_calculation = true;  // the pose is all the benchmark uses

  mrpt::math::CMatrixDouble44 start;
  start.asEigen() = guess.matrix();
  mrpt::slam::CICP::TReturnInfo info;
  const auto pdf =
      icp.Align3D(map_.get(), scans_.at(scan).get(), mrpt::poses::CPose3D(start), info);
  Attempt attempt;
  attempt.pose.matrix() =
      pdf->getMeanVal().getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen();
  return attempt;
}

}  // namespace ndtom::regbench
