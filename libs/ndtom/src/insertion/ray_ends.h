// Stage 2 of a scan's insertion: the used points' ray ends keyed by their cell and sorted,
// so the ends of a cell come together, a block's cells in a row and in offset order.
// Private to the library.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "insertion/classify_points.h"
#include "insertion/scan_context.h"
#include "ndtom/map/block_grid.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

/// Each used point as one word: its end cell's key (the cell's dense index, block number *
/// kBlockCells + offset in the block, times 2, plus 1 for a hit) above the point's index.
struct SortedRayEnds {
  std::vector<uint64_t> words;  ///< sorted by key; points of equal keys in input order
  std::vector<uint64_t> sort_buffer;
  int point_bits = 1;  ///< low bits of a word that hold the point
  uint64_t point_mask = 1;

  uint64_t keyOf(uint64_t word) const { return word >> point_bits; }
  size_t pointOf(uint64_t word) const { return size_t(word & point_mask); }
  static bool isHit(uint64_t key) { return (key & 1) != 0; }
  /// Block number * kBlockCells + offset in the block.
  static uint64_t denseIndex(uint64_t key) { return key >> 1; }
};

/// Keys and sorts the ray ends of the used points of `points` into `out`; with `hits_in`,
/// only the hits that end in its tiles (a distributed build's process whose rays are per
/// point: nothing else reads the groups), in the same order as among all. Throws
/// std::invalid_argument if the keys cannot fit a word (a scan spread over kilometres).
void sortRayEnds(const ScanContext& scan, const ClassifiedPoints& points,
                 const TileOwnership* hits_in, SortedRayEnds& out);

}  // namespace ndtom
