#include "registration/coarse_gaussians.h"

#include <algorithm>
#include <unordered_map>

#include "ndtom/map/map_queries.h"

namespace ndtom::registration {

std::vector<Gaussian> occupiedCoarseGaussians(const NdtMap& map, int factor) {
  const double r = map.options().resolution;
  const GridGeometry coarse_geometry(r * factor);
  const double half_coarse = 0.5 * r * factor;
  std::unordered_map<CellIndex, CellStats, CellIndexHash> merged;
  std::vector<CellIndex> order;  // of first appearance: deterministic, as the visit is
  map.forEachCellOrdered([&](const CellView& fine) {
    if (!fine.stats) return;  // with occupancy, only occupied cells hold statistics
    const CellIndex index = cellwiseFloorDiv(fine.index, factor);
    auto [it, inserted] = merged.try_emplace(index);
    if (inserted) order.push_back(index);
    // Fine centre minus coarse centre, from small integers: exact for dyadic resolutions.
    Eigen::Vector3d offset;
    for (int a = 0; a < 3; ++a)
      offset[a] = r * (double(fine.index[a] - index[a] * factor) + 0.5 - 0.5 * factor);
    it->second.merge(fine.stats->shifted(-offset));
    it->second.clampMean(half_coarse);
  });
  std::vector<Gaussian> out;
  for (const CellIndex& index : order) {
    const CellStats& stats = merged.at(index);
    if (!stats.hasGaussian()) continue;
    Gaussian g;
    g.cell = index;
    g.n = stats.n;
    g.mean = coarse_geometry.cellCenter(index) + stats.relative_mean;
    g.covariance = regularizedCovariance(stats.covariance(), map.options().regularization);
    out.push_back(g);
  }
  return out;
}

}  // namespace ndtom::registration
