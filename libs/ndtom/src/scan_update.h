// One scan's update of an NDT-OM (paper Sec. III): private to the library.
#pragma once

#include <Eigen/Core>
#include <array>
#include <vector>

#include "ndtom/block_grid.h"
#include "ndtom/ndt_map.h"

namespace ndtom {

/// Where a used point's ray ends: a hit, or the max-range end of a truncated ray.
struct RayEnd {
  CellIndex cell;
  uint32_t point;  ///< index into ScanUpdater::ends_
  bool hit;
};

/// Rays that end in one cell: the unit of Eq. 12's N_p and of the per-hit-cell ray mode.
struct EndGroup {
  CellIndex cell;
  bool hit;
  uint32_t count;
  CellStats batch;  ///< the group's endpoints, centred on the cell (hits only)
  Eigen::Vector3d mean_end;
};

/// Free-ray counts N_e of one scan, in blocks shaped like the map's.
struct CountBlock {
  std::array<uint32_t, kBlockCells> count{};
};

class ScanUpdater {
 public:
  ScanUpdater(NdtMap& map, const InsertOptions& options) : map_(map), options_(options) {}

  InsertionReport run(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin);

 private:
  void classifyPoints(const std::vector<Eigen::Vector3d>& points);
  void groupEndsByCell();
  void traceFreeRays();
  void applyToMap();
  void updateCell(NdtMap::Block& block, int offset, double delta_logodds, const CellStats* batch);

  NdtMap& map_;
  const InsertOptions& options_;
  InsertionReport report_;
  Eigen::Vector3d origin_;
  std::vector<Eigen::Vector3d> ends_;  ///< hit points and truncated ray ends, world frame
  std::vector<RayEnd> ray_ends_;
  std::vector<EndGroup> groups_;
  BlockGrid<CountBlock> free_counts_;
};

}  // namespace ndtom
