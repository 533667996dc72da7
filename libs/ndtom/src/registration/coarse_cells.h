// One level of the registration pyramid, cell by cell: the occupied Gaussian of a coarse
// cell made from the map's fine cells inside it, so that a level can be built whole or redone
// where the map changed, with the same bits either way. Private to the library.
#pragma once

#include <functional>
#include <optional>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/map/stats_changes.h"
#include "ndtom/matching/gaussian_lookup.h"
#include "support/parallel.h"

namespace ndtom::registration {

/// Which of the map's blocks (blockOf() coordinates) count; an empty filter: all.
using BlockFilter = std::function<bool(const CellIndex& block)>;

class CoarseCells {
 public:
  /// `factor` ≥ 1 times coarser than `map`, from the blocks `members` admits.
  CoarseCells(const NdtMap& map, int factor, const BlockFilter& members);

  const GridGeometry& geometry() const { return geometry_; }
  /// The coarse cell's Gaussian: for factor 1 the fine cell's if it is occupied; else the
  /// RCU merge of the fine cells with statistics in ascending block order and offset order
  /// (NdtMap::coarsened()'s order, so the same bits), if it has N ≥ 3, covariance
  /// regularised. A coarse cell is occupied whenever a fine cell with statistics is (with
  /// occupancy only occupied cells hold statistics, and a coarse cell's log-odds is the
  /// largest of its cells').
  std::optional<PreparedGaussian> gaussian(const CellIndex& coarse_cell) const;
  /// The coarse cells over the given fine cells (of member blocks only, if
  /// `members_only`) as the coarse grid's blocks with a bit per cell, in ascending block
  /// order; the same for any thread count.
  std::vector<BlockCells> blocksOver(const std::vector<BlockCells>& fine, bool members_only,
                                     const Threads& threads) const;
  /// blocksOver()'s cells, each once, in inBlockOrder().
  std::vector<CellIndex> cellsOver(const std::vector<BlockCells>& fine, bool members_only,
                                   const Threads& threads) const;
  /// The fine cells with statistics of the member blocks, block by block in no particular
  /// order: what every level of a new pyramid is made from.
  std::vector<BlockCells> statsCells() const;
  bool member(const CellIndex& block) const { return !members_ || members_(block); }

 private:
  const NdtMap& map_;
  int factor_;
  BlockFilter members_;
  GridGeometry geometry_;
};

}  // namespace ndtom::registration
