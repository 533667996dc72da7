#include "ndtom/map/rigid_move.h"

#include <algorithm>
#include <array>
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

  // A new cell's centre comes from at most √3/2 cells away: it lies among the 27 cells around
  // the image of an old centre. Where each of those falls when moved back, relative to the
  // moved-back image centre, in cells: the same offsets for every cell.
  std::array<Eigen::Vector3d, 27> back_offsets;
  std::array<CellIndex, 27> offsets;
  for (int i = 0; i < 27; ++i) {
    offsets[size_t(i)] = {i % 3 - 1, i / 3 % 3 - 1, i / 9 - 1};
    const Eigen::Vector3d d(offsets[size_t(i)].x, offsets[size_t(i)].y, offsets[size_t(i)].z);
    back_offsets[size_t(i)] = rotation.transpose() * d;
  }
  const double inv_r = 1.0 / map.options().resolution;

  std::vector<std::pair<CellIndex, float>> occupancy;
  occupancy.reserve(map.numCells() + map.numCells() / 4);
  std::unordered_map<CellIndex, MovedStats, CellIndexHash> moved_stats;
  // In block order: where statistics meet in one cell their RCU merges run in an order that
  // does not depend on the hash table's history (exact, not associative in floating point).
  map.forEachCellOrdered([&](const CellView& c) {
    const Eigen::Vector3d centre = grid.cellCenter(c.index);
    const CellIndex image = movedCell(motion * centre);
    // Each new cell is taken by the one old cell holding its moved-back centre, so none is
    // listed twice: here those of the 27 whose centre comes back into this cell.
    const Eigen::Vector3d base = (back * grid.cellCenter(image) - centre) * inv_r;
    for (size_t i = 0; i < 27; ++i) {
      const Eigen::Vector3d u = base + back_offsets[i];
      if (u.x() < -0.5 || u.x() >= 0.5 || u.y() < -0.5 || u.y() >= 0.5 || u.z() < -0.5 ||
          u.z() >= 0.5)
        continue;
      const CellIndex t{image.x + offsets[i].x, image.y + offsets[i].y, image.z + offsets[i].z};
      if (isSupportedCell(t)) occupancy.emplace_back(t, c.logodds);
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
  for (const auto& [index, logodds] : occupancy) out.setCell(index, logodds, none);
  // Sorted: the cells' statistics set in an order independent of the hash table's.
  std::vector<std::pair<CellIndex, MovedStats>> stats(moved_stats.begin(), moved_stats.end());
  std::sort(stats.begin(), stats.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [index, moved] : stats) {
    // Where none of the old cells is under its centre (at known space's border), the
    // statistics bring their own log-odds.
    const auto resampled = out.cell(index);
    const float logodds = resampled ? std::max(resampled->logodds, moved.logodds) : moved.logodds;
    out.setCell(index, logodds, moved.stats);
  }
  out.shrinkToFit();
  return out;
}

}  // namespace ndtom
