// Which tiles of space one process of a distributed build owns. Space is cut into cubic tiles
// of `tile_blocks` blocks a side (as in tiled_map.h); a hash of the tile's coordinates picks
// its owner among `ranks` processes. A process inserts every scan but changes only the cells
// of its own tiles (NdtMap::insertScanPart), and cells are independent under insertion, so
// the processes' maps put together are the serial map exactly, clamping included.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "ndtom/map/block_grid.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/tile_index.h"

namespace ndtom {

struct TileOwnership {
  int tile_blocks = 1;  ///< tile edge in blocks
  int rank = 0;         ///< this process, 0..ranks-1
  int ranks = 1;

  /// Throws std::invalid_argument for a tile size outside 1..kMaxTileBlocks or a rank outside
  /// 0..ranks-1.
  void validate() const {
    if (tile_blocks < 1 || tile_blocks > kMaxTileBlocks)
      throw std::invalid_argument("TileOwnership: tile_blocks " + std::to_string(tile_blocks) +
                                  " is not in 1.." + std::to_string(kMaxTileBlocks));
    if (ranks < 1 || rank < 0 || rank >= ranks)
      throw std::invalid_argument("TileOwnership: rank " + std::to_string(rank) + " of " +
                                  std::to_string(ranks) + " processes");
  }

  /// The rank that owns a tile. A mixing hash, not the coordinates modulo ranks: neighbouring
  /// tiles (which one scan touches together) go to different ranks, so each scan's work is
  /// spread over them.
  int ownerOfTile(const CellIndex& tile) const {
    uint64_t h = uint64_t(uint32_t(tile.x)) * 0x9E3779B97F4A7C15ull;
    h ^= uint64_t(uint32_t(tile.y)) * 0xC2B2AE3D27D4EB4Full;
    h ^= uint64_t(uint32_t(tile.z)) * 0x165667B19E3779F9ull;
    h ^= h >> 29;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 32;
    return int(h % uint64_t(ranks));
  }
  bool ownsTile(const CellIndex& tile) const { return ranks == 1 || ownerOfTile(tile) == rank; }
  bool ownsBlock(const CellIndex& block) const {
    return ownsTile(tileOfBlock(block, tile_blocks));
  }
  int tileCells() const { return tile_blocks * kBlockEdge; }  ///< tile edge in cells
};

}  // namespace ndtom
