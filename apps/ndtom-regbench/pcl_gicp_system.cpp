// pcl-gicp: pcl::GeneralizedIterativeClosestPoint (plane to plane, covariances from the 20
// nearest neighbours) on voxel-filtered clouds.
#include <pcl/registration/gicp.h>

#include <cstdio>

#include "pcl_peers.h"
#include "pcl_system.h"

namespace ndtom::regbench {

namespace {

constexpr float kTargetLeaf = 0.2f;  // m, VoxelGrid of the map points
constexpr float kSourceLeaf = 0.2f;  // m, VoxelGrid of the scan
/// m: correspondences farther apart are ignored; large enough for the starts' offsets
/// (a point 10 m away moves by 1.7 m when the guess is turned 10°). 1 m: 3/12 at 3 m / 30°;
/// 2 m: 10/12; 3 m: 10/12, and 8/12 instead of 6/12 at 5 m / 45°, at the same accuracy.
constexpr double kMaxCorrespondence = 3.0;
constexpr int kMaxIterations = 100;
constexpr double kEpsilon = 1e-6;  // m, translation step that ends the search

class PclGicpSystem : public PclSystem {
 public:
  explicit PclGicpSystem(const MapScans& map) {
    target_ = voxelFiltered(toPclCloud(map.near_points), kTargetLeaf);
    gicp_.setInputTarget(target_);  // its covariances are computed by the first align()
    gicp_.setMaxCorrespondenceDistance(kMaxCorrespondence);
    gicp_.setMaximumIterations(kMaxIterations);
    gicp_.setTransformationEpsilon(kEpsilon);
  }

  std::string label() const override { return "pcl-gicp"; }
  std::string settings() const override {
    char text[300];
    std::snprintf(text, sizeof text,
                  "GeneralizedIterativeClosestPoint: target %zu points (VoxelGrid %g m of the "
                  "map points), source: VoxelGrid %g m; max correspondence distance %g m, <= %d "
                  "iterations, transformation epsilon %g, %d neighbours per covariance",
                  target_->size(), kTargetLeaf, kSourceLeaf, kMaxCorrespondence, kMaxIterations,
                  kEpsilon, gicp_.getCorrespondenceRandomness());
    return text;
  }

 protected:
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>& registration() override { return gicp_; }
  float sourceLeaf() const override { return kSourceLeaf; }

 private:
  pcl::GeneralizedIterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> gicp_;
  PclCloud::Ptr target_;
};

}  // namespace

std::unique_ptr<RegistrationSystem> makePclGicp(const MapScans& map) {
  return std::make_unique<PclGicpSystem>(map);
}

}  // namespace ndtom::regbench
