#include "ndtom_system.h"

#include <cmath>
#include <cstdio>

namespace ndtom::regbench {

NdtMap buildNdtMap(const LidarSequence& sequence, const std::vector<int>& scans, double resolution,
                   double max_range) {
  MapOptions options;
  options.resolution = resolution;
  options.scan.max_range = max_range;
  NdtMap map(options);
  std::vector<Eigen::Vector3d> world;
  for (int i : scans) {
    const Eigen::Isometry3d& pose = sequence.poses[size_t(i)];
    world.clear();
    for (const Eigen::Vector3d& p : sequence.scans[size_t(i)]) world.push_back(pose * p);
    map.insertScan(world, pose.translation());
  }
  return map;
}

NdtomSystem::NdtomSystem(const NdtMap& map, RegistrationMethod method, int threads) : map_(map) {
  RegistrationOptions options;
  options.method = method;
  options.threads = threads;
  registration_.setOptions(options);
}

std::string NdtomSystem::label() const {
  const RegistrationOptions& o = registration_.options();
  return std::string(o.method == RegistrationMethod::P2D ? "ndtom-p2d" : "ndtom-d2d") + "/t" +
         std::to_string(o.threads);
}

std::string NdtomSystem::settings() const {
  const RegistrationOptions& o = registration_.options();
  std::string levels;
  for (int f : o.level_factors) {
    char cell[32];
    std::snprintf(cell, sizeof cell, "%s%g", levels.empty() ? "" : "/",
                  f * map_.options().resolution);
    levels += cell;
  }
  char text[400];
  std::snprintf(text, sizeof text,
                "NdtRegistration %s, default options: levels %s m, outlier ratio %g, <= %d "
                "Newton steps per level, steps < %g m and %g rad end a level, matched >= %g; "
                "threads %d",
                toString(o.method), levels.c_str(), o.outlier_ratio, o.max_iterations,
                o.translation_epsilon, o.rotation_epsilon, o.min_matched_fraction, o.threads);
  std::string out = text;
  if (o.method == RegistrationMethod::P2D) {
    std::snprintf(text, sizeof text,
                  "; scan: voxel centroids of %g x the level's cell, <= %zu "
                  "points per level",
                  o.voxel_ratio, o.max_points);
    out += text;
  }
  return out;
}

void NdtomSystem::setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) {
  scans_ = scans;
}

Attempt NdtomSystem::align(size_t scan, const Eigen::Isometry3d& guess) {
  const RegistrationResult r = registration_.align(map_, *scans_.at(scan), guess);
  return {r.pose, r.converged, r.failure, r.score, r.matched_fraction, r.levels};
}

}  // namespace ndtom::regbench
