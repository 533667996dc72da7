#include "ndtom/map/rigid_move.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>
#include <utility>
#include <vector>

namespace ndtom {
namespace {

void checkRigid(const Eigen::Isometry3d& motion) {
  if (!motion.matrix().allFinite()) throw std::invalid_argument("movedMap: the motion is not finite");
  const Eigen::Matrix3d r = motion.linear();
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).norm() > 1e-9 || r.determinant() < 0)
    throw std::invalid_argument("movedMap: the motion's rotation is not a rotation matrix");
}

struct MovedStats {
  CellStats stats;
  float logodds = 0;  ///< the largest of the cells the statistics came from
};

}  // namespace

NdtMap movedMap(const NdtMap& map, const Eigen::Isometry3d& motion) {
  checkRigid(motion);
  const GridGeometry& grid = map.geometry();
  const double half = 0.5 * map.options().resolution;
  const Eigen::Matrix3d rotation = motion.linear();
  const Eigen::Isometry3d back = motion.inverse();
  const auto movedCell = [&](const Eigen::Vector3d& p) {
    if (!grid.inRange(p))
      throw std::invalid_argument("movedMap: the motion takes cells beyond the supported range");
    return grid.cellOf(p);
  };

  std::vector<std::pair<CellIndex, float>> occupancy;
  occupancy.reserve(map.numCells() + map.numCells() / 4);
  std::unordered_map<CellIndex, MovedStats, CellIndexHash> moved_stats;
  // In block order: where statistics meet in one cell their RCU merges run in an order that
  // does not depend on the hash table's history (exact, not associative in floating point).
  map.forEachCellOrdered([&](const CellView& c) {
    const Eigen::Vector3d centre = grid.cellCenter(c.index);
    // A new cell's centre comes from at most √3/2 cells away: it lies among the 27 cells
    // around the image of this centre. Each new cell is taken by the one old cell holding its
    // moved-back centre, so none is listed twice.
    const CellIndex image = movedCell(motion * centre);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const CellIndex t{image.x + dx, image.y + dy, image.z + dz};
          if (isSupportedCell(t) && grid.cellOf(back * grid.cellCenter(t)) == c.index)
            occupancy.emplace_back(t, c.logodds);
        }
    if (!c.stats) return;
    const Eigen::Vector3d mean = motion * (centre + c.stats->relative_mean);
    const CellIndex target = movedCell(mean);
    CellStats s;
    s.n = c.stats->n;
    s.relative_mean = mean - grid.cellCenter(target);
    const Eigen::Matrix3d scatter = rotation * c.stats->scatter * rotation.transpose();
    s.scatter = 0.5 * (scatter + scatter.transpose());  // rounding leaves it a few ulps off
    s.clampMean(half);
    const auto [it, first] = moved_stats.try_emplace(target, MovedStats{s, c.logodds});
    if (!first) {
      it->second.stats.merge(s);
      it->second.stats.clampMean(half);
      it->second.logodds = std::max(it->second.logodds, c.logodds);
    }
  });

  NdtMap out(map.options());
  const CellStats none;
  for (const auto& [index, logodds] : occupancy) {
    const auto it = moved_stats.find(index);
    if (it == moved_stats.end()) {
      out.setCell(index, logodds, none);
      continue;
    }
    out.setCell(index, std::max(logodds, it->second.logodds), it->second.stats);
    moved_stats.erase(it);
  }
  // Statistics whose mean left the cells resampled from known space (at its border).
  std::vector<std::pair<CellIndex, MovedStats>> rest(moved_stats.begin(), moved_stats.end());
  std::sort(rest.begin(), rest.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [index, moved] : rest) out.setCell(index, moved.logodds, moved.stats);
  out.shrinkToFit();
  return out;
}

}  // namespace ndtom
