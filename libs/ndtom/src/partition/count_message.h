// The message of free-space counts one process of a distributed build sends another when the
// rays are shared out (count_exchange.h): per block, its coordinates, the number n of its
// cells counted, then n pairs (offset in the block, count). Private to the library.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

/// Appends a block's non-zero counts (`counts`: kBlockCells of them, in offset order). A block
/// with no count goes too: the walk that entered it made it part of the scan.
void appendCountBlock(const CellIndex& block, const uint32_t* counts, std::vector<uint32_t>& words);

/// Adds the counts of a message to `countsOf(block)` (kBlockCells counters of that block).
/// Throws std::runtime_error for a malformed message, or one naming a block `owned` does not
/// own; counts added before the error stay added.
void addCountMessage(const std::vector<uint32_t>& words, const TileOwnership& owned,
                     const std::function<uint32_t*(const CellIndex& block)>& countsOf);

}  // namespace ndtom
