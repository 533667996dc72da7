#include "octomap_system.h"

#include <octomap/OcTree.h>

namespace ndtom::bench {

OctomapSystem::OctomapSystem(double resolution, double max_range)
    : resolution_(resolution),
      max_range_(max_range),
      cloud_(std::make_unique<octomap::Pointcloud>()) {}

OctomapSystem::~OctomapSystem() = default;

void OctomapSystem::reset() {
  tree_.reset();
  tree_ = std::make_unique<octomap::OcTree>(resolution_);
}

void OctomapSystem::prepareScan(const Scan& scan) {
  cloud_->clear();
  cloud_->reserve(scan.points.size());
  for (const Eigen::Vector3d& p : scan.points)
    cloud_->push_back(float(p.x()), float(p.y()), float(p.z()));
}

void OctomapSystem::insertScan(const Scan& scan) {
  const octomap::point3d origin(float(scan.origin.x()), float(scan.origin.y()),
                                float(scan.origin.z()));
  tree_->insertPointCloud(*cloud_, origin, max_range_, /*lazy_eval=*/false, /*discretize=*/false);
}

uint64_t OctomapSystem::lastScanVisits(const Scan& scan) {
  const octomap::point3d origin(float(scan.origin.x()), float(scan.origin.y()),
                                float(scan.origin.z()));
  octomap::KeyRay ray;
  uint64_t visits = 0;
  for (size_t i = 0; i < cloud_->size(); ++i) {
    const octomap::point3d& p = (*cloud_)[i];
    // The same branches as OccupancyOcTreeBase::computeUpdate (no bounding box).
    if ((p - origin).norm() <= max_range_) {
      if (tree_->computeRayKeys(origin, p, ray)) visits += ray.size();
    } else {
      const octomap::point3d end = origin + (p - origin).normalized() * float(max_range_);
      if (tree_->computeRayKeys(origin, end, ray)) visits += ray.size();
    }
  }
  return visits;
}

MapSize OctomapSystem::mapSize() const {
  return {tree_->getNumLeafNodes(), tree_->memoryUsage()};
}

}  // namespace ndtom::bench
