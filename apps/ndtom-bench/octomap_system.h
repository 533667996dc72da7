// OctoMap 1.9.7 under test: OcTree::insertPointCloud with the same origin, max range and
// resolution (probabilistic update, pruning, no lazy evaluation, no discretisation).
#pragma once

#include <memory>

#include "mapping_system.h"

namespace octomap {
class OcTree;
class Pointcloud;
}  // namespace octomap

namespace ndtom::bench {

class OctomapSystem : public MappingSystem {
 public:
  OctomapSystem(double resolution, double max_range);
  ~OctomapSystem() override;

  std::string label() const override { return "octomap"; }
  void reset() override;
  void prepareScan(const Scan& scan) override;
  void insertScan(const Scan& scan) override;
  /// Exact: the free-space keys computeRayKeys returns for every ray, traced as computeUpdate
  /// does (truncated at max range; end cell excluded, as NDT-OM counts). Recomputed untimed.
  uint64_t lastScanVisits(const Scan& scan) override;
  MapSize mapSize() const override;

 private:
  double resolution_;
  double max_range_;
  std::unique_ptr<octomap::OcTree> tree_;
  std::unique_ptr<octomap::Pointcloud> cloud_;
};

}  // namespace ndtom::bench
