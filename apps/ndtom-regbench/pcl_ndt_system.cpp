// pcl-ndt: pcl::NormalDistributionsTransform with 1 m cells. With PCL's default transformation
// epsilon (0.01, compared with the squared length of a step) it stops after one step on these
// scans, so the epsilon is 1e-6. Its line search moves at most `step size` per iteration (in
// the norm of the 6-vector x y z roll pitch yaw): the tutorial's 0.1 with 35 iterations cannot
// travel back from 3 m / 30° (0/12 there); 0.5 and 100 iterations can (see
// doc/registration/benchmark.md for the settings tried).
#include <pcl/registration/ndt.h>

#include <cstdio>

#include "pcl_peers.h"
#include "pcl_system.h"

namespace ndtom::regbench {

namespace {

constexpr float kCell = 1.0f;      // m, the target's NDT cells
constexpr double kEpsilon = 1e-6;  // m², squared step length that ends the search
constexpr double kStepSize = 0.5;  // the More-Thuente line search's largest step
constexpr int kMaxIterations = 100;
// m, the scan's VoxelGrid (0.2 m: half the time, 5/12 instead of 7/12 at 3 m / 30°).
constexpr float kSourceLeaf = 0.1f;

class PclNdtSystem : public PclSystem {
 public:
  explicit PclNdtSystem(const MapScans& map) {
    ndt_.setResolution(kCell);
    ndt_.setTransformationEpsilon(kEpsilon);
    ndt_.setStepSize(kStepSize);
    ndt_.setMaximumIterations(kMaxIterations);
    target_ = toPclCloud(map.near_points);
    ndt_.setInputTarget(target_);  // builds the target's cells
  }

  std::string label() const override { return "pcl-ndt"; }
  std::string settings() const override {
    char text[300];
    std::snprintf(text, sizeof text,
                  "NormalDistributionsTransform: target %zu map points in %g m cells, source: "
                  "VoxelGrid %g m; transformation epsilon %g, step size %g, <= %d iterations, "
                  "outlier ratio %g (PCL's default)",
                  target_->size(), kCell, kSourceLeaf, kEpsilon, kStepSize, kMaxIterations,
                  ndt_.getOulierRatio());  // sic: PCL 1.13's spelling
    return text;
  }

 protected:
  pcl::Registration<pcl::PointXYZ, pcl::PointXYZ>& registration() override { return ndt_; }
  float sourceLeaf() const override { return kSourceLeaf; }

 private:
  pcl::NormalDistributionsTransform<pcl::PointXYZ, pcl::PointXYZ> ndt_;
  PclCloud::Ptr target_;
};

}  // namespace

bool pclAvailable() {
  return true;
}

std::string pclVersion() {
  return PCL_VERSION_PRETTY;
}

std::unique_ptr<RegistrationSystem> makePclNdt(const MapScans& map) {
  return std::make_unique<PclNdtSystem>(map);
}

}  // namespace ndtom::regbench
