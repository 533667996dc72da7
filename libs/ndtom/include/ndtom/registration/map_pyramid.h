// A map's exact coarsenings (paper Sec. III-B) prepared as registration targets, coarse to
// fine: each level keeps only the Gaussians of occupied cells, looked up by cell.
//
// Threading: immutable after construction; concurrent reads are safe.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/matching/gaussian_lookup.h"

namespace ndtom {

class MapPyramid {
 public:
  /// Levels `factors` times coarser than `map` (each ≥ 1, given coarse to fine, e.g.
  /// {16, 8, 4, 2, 1}), built on up to `threads` threads (one per level; the same levels for
  /// any count); throws std::invalid_argument for a bad list, and MemoryBudgetError when
  /// the levels with the map would pass the map's memory budget (ScanOptions::memory_budget).
  MapPyramid(const NdtMap& map, const std::vector<int>& factors, int threads = 1);

  size_t size() const { return levels_.size(); }
  int factor(size_t level) const { return factors_[level]; }
  double resolution(size_t level) const { return levels_[level]->geometry().resolution(); }
  const GaussianLookup& level(size_t level) const { return *levels_[level]; }
  /// NdtMap::revision() of the map the levels come from.
  uint64_t revision() const { return revision_; }
  const std::vector<int>& factors() const { return factors_; }

 private:
  std::vector<int> factors_;
  std::vector<std::unique_ptr<const GaussianLookup>> levels_;
  uint64_t revision_;
};

}  // namespace ndtom
