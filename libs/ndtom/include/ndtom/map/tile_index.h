// Space cut into cubic tiles of a whole number of blocks a side: the unit a tiled map file
// stores, an out-of-core map spills and a distributed build hands to one process.
#pragma once

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"

namespace ndtom {

/// Largest tile edge in blocks: bounds what a tiled file may claim, so a corrupt one cannot
/// make a reader loop over absurd tiles.
constexpr int kMaxTileBlocks = 4096;

/// The tile of a block, for tiles of `tile_blocks` blocks a side.
inline CellIndex tileOfBlock(const CellIndex& block, int tile_blocks) {
  return cellwiseFloorDiv(block, tile_blocks);
}

/// The tile of a cell, for tiles of `tile_blocks` blocks a side.
inline CellIndex tileOfCell(const CellIndex& cell, int tile_blocks) {
  return cellwiseFloorDiv(cell, tile_blocks * kBlockEdge);
}

}  // namespace ndtom
