// Space cut into cubic tiles of a whole number of blocks a side: the unit a tiled map file
// stores, an out-of-core map spills and a distributed build hands to one process.
#pragma once

#include <cstdint>

#include "ndtom/cell_index.h"

namespace ndtom {

/// Largest tile edge in blocks: bounds what a tiled file may claim, so a corrupt one cannot
/// make a reader loop over absurd tiles.
constexpr int kMaxTileBlocks = 4096;

/// The cube of `edge` a side that holds `index`: a block's tile for an edge in blocks, a
/// cell's for an edge in cells.
inline CellIndex tileHolding(const CellIndex& index, int32_t edge) {
  return {floorDiv(index.x, edge), floorDiv(index.y, edge), floorDiv(index.z, edge)};
}

/// The tile of a block, for tiles of `tile_blocks` blocks a side.
inline CellIndex tileOfBlock(const CellIndex& block, int tile_blocks) {
  return tileHolding(block, tile_blocks);
}

}  // namespace ndtom
