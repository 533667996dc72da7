// Where a map's statistics changed in its last insertion, for what is derived from them and
// follows the map (the registration pyramid of an online mapper): it redoes those cells only.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"

namespace ndtom {

/// Cells of one block, a bit each at offsetInBlock().
struct BlockCells {
  CellIndex block;
  std::array<uint64_t, kBlockCells / 64> cells{};
};

struct StatsChanges {
  /// The map's revision() before and after the change; `from` is 0 when what changed is not
  /// known (the last change was not an insertion, or it failed): derived data is rebuilt.
  uint64_t from = 0, to = 0;
  /// Every cell whose statistics may have changed (the scan's hit cells and the cells its
  /// rays emptied), a superset of those that did; in no particular order, and a block may
  /// have several entries (sorting them would be serial work in every insertion, for the
  /// followers that want them).
  std::vector<BlockCells> blocks;
};

}  // namespace ndtom
