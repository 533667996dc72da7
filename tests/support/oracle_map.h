// A slow, obviously-correct NDT-OM: std::map of cells, brute-force ray/cell intersection,
// per-cell point lists and two-pass statistics. The reference for the map tests, in both ray
// modes (PerHitCell: one ray per cell of ends, to their mean, weighted by their number).
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <vector>

#include "ndtom/map/options.h"
#include "support/brute_force.h"

namespace ndtom::testing {

struct OracleCell {
  float logodds = 0;
  std::vector<Eigen::Vector3d> points;  ///< points behind the current Gaussian
};

class OracleMap {
 public:
  explicit OracleMap(const MapOptions& o) : options_(o), geometry_(o.resolution) {}

  void insert(const std::vector<Eigen::Vector3d>& points, const Eigen::Vector3d& origin) {
    std::map<CellIndex, int> hits, misses;
    std::map<CellIndex, std::vector<Eigen::Vector3d>> scan_points;
    // PerHitCell: the ends grouped by cell and by hit or not, one ray per group.
    std::map<std::pair<CellIndex, bool>, std::vector<Eigen::Vector3d>> groups;
    const bool per_cell = options_.scan.ray_mode == RayMode::PerHitCell;
    for (const auto& p : points) {
      if (!p.allFinite()) continue;
      const double range = (p - origin).norm();
      if (range == 0 || range < options_.scan.min_range) continue;
      Eigen::Vector3d end = p;
      const bool hit = range <= options_.scan.max_range;
      if (!hit) end = origin + (p - origin) * (options_.scan.max_range / range);
      if (hit) {
        hits[geometry_.cellOf(p)]++;
        scan_points[geometry_.cellOf(p)].push_back(p);
      }
      if (!options_.occupancy.enabled) continue;
      if (per_cell)
        groups[{geometry_.cellOf(end), hit}].push_back(end);
      else
        for (const CellIndex& c : bruteForce(geometry_, origin, end)) misses[c]++;
    }
    // One ray to the mean of a group's ends (relative to the cell centre, as the map sums
    // them), counting for every end.
    for (const auto& [key, ends] : groups) {
      const Eigen::Vector3d centre = geometry_.cellCenter(key.first);
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (const auto& e : ends) mean += e - centre;
      mean /= double(ends.size());
      for (const CellIndex& c : bruteForce(geometry_, origin, centre + mean))
        misses[c] += int(ends.size());
    }
    const double lh = std::log(options_.occupancy.p_hit / (1 - options_.occupancy.p_hit));
    const double lm = std::log(options_.occupancy.p_miss / (1 - options_.occupancy.p_miss));
    auto update = [&](const CellIndex& c, double delta) {
      OracleCell& cell = cells_[c];
      cell.logodds = float(std::clamp(double(cell.logodds) + delta, options_.occupancy.logodds_min,
                                      options_.occupancy.logodds_max));
      if (options_.occupancy.enabled && cell.logodds <= 0) {
        cell.points.clear();
      } else {
        const auto& new_points = scan_points[c];
        cell.points.insert(cell.points.end(), new_points.begin(), new_points.end());
      }
    };
    for (const auto& [c, n] : hits) update(c, n * lh);
    for (const auto& [c, n] : misses)
      if (!hits.count(c)) update(c, n * lm);
  }

  const std::map<CellIndex, OracleCell>& cells() const { return cells_; }

 private:
  MapOptions options_;
  GridGeometry geometry_;
  std::map<CellIndex, OracleCell> cells_;
};

}  // namespace ndtom::testing
