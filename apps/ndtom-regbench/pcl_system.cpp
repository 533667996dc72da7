#include "pcl_system.h"

#include <pcl/filters/voxel_grid.h>

namespace ndtom::regbench {

namespace {

/// A registration's float matrix as our pose, the rotation made orthonormal again, so that
/// the errors measure the registration, not float rounding.
Eigen::Isometry3d toIsometry(const Eigen::Matrix4f& m) {
  const Eigen::Matrix4d d = m.cast<double>();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() =
      Eigen::Quaterniond(Eigen::Matrix3d(d.topLeftCorner<3, 3>())).normalized().toRotationMatrix();
  pose.translation() = d.topRightCorner<3, 1>();
  return pose;
}

}  // namespace

PclCloud::Ptr toPclCloud(const std::vector<Eigen::Vector3d>& points) {
  auto cloud = std::make_shared<PclCloud>();
  cloud->reserve(points.size());
  for (const Eigen::Vector3d& p : points)
    cloud->push_back({float(p.x()), float(p.y()), float(p.z())});
  return cloud;
}

PclCloud::Ptr voxelFiltered(const PclCloud::ConstPtr& cloud, float leaf) {
  pcl::VoxelGrid<pcl::PointXYZ> grid;
  grid.setLeafSize(leaf, leaf, leaf);
  grid.setInputCloud(cloud);
  auto out = std::make_shared<PclCloud>();
  grid.filter(*out);
  return out;
}

void PclSystem::setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) {
  scans_.clear();
  for (const auto* scan : scans) scans_.push_back(toPclCloud(*scan));
}

Attempt PclSystem::align(size_t scan, const Eigen::Isometry3d& guess) {
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>& r = registration();
  r.setInputSource(voxelFiltered(scans_.at(scan), sourceLeaf()));
  PclCloud aligned;
  r.align(aligned, guess.matrix().cast<float>());
  Attempt attempt;
  attempt.pose = toIsometry(r.getFinalTransformation());
  return attempt;
}

}  // namespace ndtom::regbench
