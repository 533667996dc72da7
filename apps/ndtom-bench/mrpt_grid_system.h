// MRPT 2.5.8's COccupancyGridMap3D under test: a dense int8 log-odds array over a fixed box,
// sized once per dataset to the region the rays can reach (untimed), traced per point with
// insertRay (what insertPointCloud does, see below).
#pragma once

#include <memory>

#include "mapping_system.h"

namespace mrpt::maps {
class COccupancyGridMap3D;
}

namespace ndtom::bench {

class MrptGridSystem : public MappingSystem {
 public:
  /// `bounds`: the box the grid must cover (m); one cell of margin is added.
  MrptGridSystem(double resolution, double max_range, const Box& bounds);
  ~MrptGridSystem() override;

  std::string label() const override { return "mrpt-grid3d"; }
  void reset() override;
  void insertScan(const Scan& scan) override;
  /// Exact: insertRay's loop makes max(|Δcx|, |Δcy|, |Δcz|) free-cell updates per ray (a
  /// fixed-point line walk, not an exact traversal); recomputed untimed from the cell indices.
  uint64_t lastScanVisits(const Scan& scan) override;
  /// Cells: voxels whose log-odds left the prior 0; memory: the whole dense array.
  MapSize mapSize() const override;

 private:
  double resolution_;
  double max_range_;
  Box bounds_;
  std::unique_ptr<mrpt::maps::COccupancyGridMap3D> grid_;
};

}  // namespace ndtom::bench
