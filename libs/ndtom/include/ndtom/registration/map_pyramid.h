// A map's exact coarsenings (paper Sec. III-B) prepared as registration targets, coarse to
// fine: each level keeps only the Gaussians of occupied cells, looked up by cell. A pyramid
// can follow a map that grows scan by scan (an online mapper's): it redoes only the coarse
// cells over the cells an insertion changed, with the same bits as a new pyramid.
//
// Threading: const members are safe to call concurrently; follow() and setMembers() are not.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/map/stats_changes.h"
#include "ndtom/matching/gaussian_lookup.h"

namespace ndtom {

class MapPyramid {
 public:
  /// Which of the map's blocks (blockOf() coordinates) the levels are made of, e.g. those
  /// near a sensor; an empty filter admits all.
  using BlockFilter = std::function<bool(const CellIndex& block)>;

  /// Levels `factors` times coarser than `map` (each ≥ 1, given coarse to fine, e.g.
  /// {16, 8, 4, 2, 1}) of the blocks `members` admits, built on up to `threads` threads (the
  /// same levels for any count); throws std::invalid_argument for a bad list, and
  /// MemoryBudgetError when the levels with the map would pass the map's memory budget
  /// (ScanOptions::memory_budget).
  MapPyramid(const NdtMap& map, const std::vector<int>& factors, int threads = 1,
             BlockFilter members = {});
  ~MapPyramid();

  size_t size() const { return levels_.size(); }
  int factor(size_t level) const { return factors_[level]; }
  double resolution(size_t level) const { return levels_[level]->geometry().resolution(); }
  const GaussianLookup& level(size_t level) const { return *levels_[level]; }
  /// NdtMap::revision() of the map the levels come from.
  uint64_t revision() const { return revision_; }
  const std::vector<int>& factors() const { return factors_; }
  /// Heap bytes of the levels.
  size_t memoryBytes() const;

  /// Brings the levels to `map`'s revision from its last insertion's changes
  /// (NdtMap::lastStatsChanges()): the same levels as a new pyramid of the map, for the cost
  /// of the coarse cells over the changed cells. Returns false, changing nothing, when the
  /// changes do not start at revision() (the map changed otherwise, or more than once since):
  /// build a new pyramid then. Throws MemoryBudgetError, changing nothing, as the constructor.
  bool follow(const NdtMap& map);
  /// Makes the levels those of the blocks `members` admits (`map` at revision(), else
  /// std::logic_error), redoing the coarse cells over the blocks that joined or left: a
  /// region that moves with a sensor. O(the map's blocks) to find them. Throws
  /// MemoryBudgetError, changing nothing, as the constructor.
  void setMembers(const NdtMap& map, BlockFilter members);

 private:
  struct Work;  // threads of the build and of the updates
  /// New levels of the coarse cells `blocks[l]` (coarse blocks with a bit per cell).
  void build(const NdtMap& map, const std::vector<std::vector<BlockCells>>& blocks);
  /// Each level's coarse cells in `cells[l]` computed again from the blocks `members` admits
  /// and put in (or out of) the level. Changes nothing if it throws.
  void redo(const NdtMap& map, const std::vector<std::vector<CellIndex>>& cells,
            const BlockFilter& members);
  // redo()'s first phase: each cell's Gaussian computed again (counting those found).
  std::vector<std::vector<CellChange>> redoCells(const NdtMap& map,
                                                 const std::vector<std::vector<CellIndex>>& cells,
                                                 const BlockFilter& members, size_t& gaussians);
  /// Throws MemoryBudgetError if `gaussians` more (beside the levels, or instead of them)
  /// would pass the map's memory budget.
  void checkBudget(const NdtMap& map, size_t gaussians, bool beside_levels) const;

  std::vector<int> factors_;
  std::vector<std::unique_ptr<GaussianLookup>> levels_;
  uint64_t revision_;
  BlockFilter members_;
  std::unique_ptr<Work> work_;
};

}  // namespace ndtom
