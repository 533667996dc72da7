#include "ndtom_eval/batch_ndt.h"

namespace ndtom {

CellStatsMap batchNdt(const std::vector<Eigen::Vector3d>& points, const GridGeometry& geometry) {
  std::unordered_map<CellIndex, std::vector<Eigen::Vector3d>, CellIndexHash> per_cell;
  for (const Eigen::Vector3d& p : points) {
    if (!geometry.inRange(p)) continue;
    const CellIndex c = geometry.cellOf(p);
    per_cell[c].push_back(p - geometry.cellCenter(c));
  }
  CellStatsMap result;
  result.reserve(per_cell.size());
  for (const auto& [cell, relative] : per_cell)
    result.emplace(cell, CellStats::fromPoints(relative));
  return result;
}

}  // namespace ndtom
