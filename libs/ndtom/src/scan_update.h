// One scan's update of an NDT-OM (paper Sec. III): private to the library.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ndtom/ndt_map.h"
#include "scan_counts.h"

namespace ndtom {

/// Where a used point's ray ends (a hit, or the max-range end of a truncated ray), keyed by
/// its cell so that sorting groups the ends of each cell together.
struct RayEnd {
  uint64_t key;    ///< dense cell index within the scan's bounding box, times 2, plus `hit`
  uint32_t point;  ///< index into ScanUpdater::ends_
};

/// Rays that end in one cell: the unit of Eq. 12's N_p and of the per-hit-cell ray mode.
struct EndGroup {
  CellIndex cell;
  bool hit;
  uint32_t count;
  CellStats batch;  ///< the group's endpoints, centred on the cell (hits only)
  Eigen::Vector3d mean_end;
};

/// Scratch memory reused from scan to scan (kept by the map, not part of its state).
struct ScanScratch {
  std::vector<Eigen::Vector3d> ends;  ///< hit points and truncated ray ends, world frame
  std::vector<CellIndex> end_cells;
  std::vector<RayEnd> ray_ends, sort_buffer;
  std::vector<EndGroup> groups;
  std::vector<ScanCounts> counts;  ///< one per thread; counts[0] receives the sum
};

class ScanUpdater {
 public:
  ScanUpdater(NdtMap& map, const InsertOptions& options, ScanScratch& scratch)
      : map_(map), options_(options), s_(scratch) {}

  InsertionReport run(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin);

 private:
  void classifyPoints(const std::vector<Eigen::Vector3d>& points);
  void groupEndsByCell();
  void traceFreeRays();
  void applyToMap();
  void applyFreeCounts(const CountBlock& counts, NdtMap::Block& block, double miss);
  void updateCell(NdtMap::Block& block, int offset, double delta_logodds, const CellStats* batch);

  NdtMap& map_;
  const InsertOptions& options_;
  ScanScratch& s_;
  InsertionReport report_;
  Eigen::Vector3d origin_;
};

}  // namespace ndtom
