// What the PCL peers share: our points as PCL clouds (float, as PCL's registration works),
// PCL's own voxel filter, and the timed call, which filters the held-out scan and registers it
// with the peer's pcl::Registration.
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/registration.h>

#include <Eigen/Geometry>
#include <vector>

#include "registration_system.h"

namespace ndtom::regbench {

using PclCloud = pcl::PointCloud<pcl::PointXYZ>;

PclCloud::Ptr toPclCloud(const std::vector<Eigen::Vector3d>& points);

/// pcl::VoxelGrid with cubes of edge `leaf` (m): one centroid per occupied cube.
PclCloud::Ptr voxelFiltered(const PclCloud::ConstPtr& cloud, float leaf);

class PclSystem : public RegistrationSystem {
 public:
  void setScans(const std::vector<const std::vector<Eigen::Vector3d>*>& scans) override;
  /// The scan through a VoxelGrid of sourceLeaf(), then registration().align() from `guess`.
  Attempt align(size_t scan, const Eigen::Isometry3d& guess) override;

 protected:
  /// The peer's registration, its target and options set.
  virtual pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>& registration() = 0;
  /// Edge of the scan's VoxelGrid (m).
  virtual float sourceLeaf() const = 0;

 private:
  std::vector<PclCloud::Ptr> scans_;
};

}  // namespace ndtom::regbench
