// A map stored as tiles, so that a program can load only the part it needs: the map's blocks
// grouped into cubic tiles of `tile_blocks` blocks a side, each tile a complete map file
// (map_io.h, with its own checksum) in one file, found through an index at the end.
//
//   "NDTOMTIL"                8-byte magic
//   u32 version               1
//   u32 tile_blocks           tile edge in blocks (1..kMaxTileBlocks, tiles.h)
//   u64 size, bytes           the map's options: an empty map in the map format
//   the tiles' map files, back to back, in tile order
//   u64 tile count, then per tile (ascending x, y, z): i32 x, y, z (tile coordinates),
//     u64 offset, u64 size, u64 known cells
//   u64 offset of the tile count above
//   u32 CRC-32 of every byte outside the tiles (which carry their own)
//
// Loading checks the index (checksum, offsets inside the file, tiles back to back and in
// order) when the file is opened, and each tile when it is loaded (its own checksum, the
// same options as the file, every cell inside the tile); it throws MapFormatError naming
// the file and never crashes. The tiles of a map, loaded together, are the map bit for bit.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "ndtom/files/map_io.h"
#include "ndtom/map/cell_index.h"
#include "ndtom/map/ndt_map.h"
#include "ndtom/map/tile_index.h"

namespace ndtom {

struct TileInfo {
  CellIndex tile;  ///< tile coordinates: cell index / (tile_blocks · kBlockEdge), rounded down
  uint64_t offset = 0, size = 0;  ///< where its map file lies in the tiled file
  uint64_t cells = 0;             ///< known cells in it
};

/// Writes `map` to `path` as tiles of `tile_blocks` blocks a side (atomically, as saveMap).
/// Throws std::invalid_argument for tile_blocks outside 1..kMaxTileBlocks, std::runtime_error
/// naming the path if it cannot be written.
void saveTiledMap(const NdtMap& map, const std::string& path, int tile_blocks);

/// Receives the tiles of a map being written, one at a time in ascending tile order, each
/// holding only cells of that tile (an empty one is skipped).
using TileSink = std::function<void(const CellIndex& tile, const NdtMap& cells)>;
/// The same, for a map that is never whole in memory: `fill` hands the tiles to the sink.
/// Throws std::invalid_argument for tiles out of order, with other options or with cells
/// outside the tile (nothing is written then).
void saveTiledMap(const MapOptions& options, const std::string& path, int tile_blocks,
                  const std::function<void(const TileSink&)>& fill);

/// The space a tile of `tile_blocks` blocks a side covers at `resolution`.
Eigen::AlignedBox3d tileBoxOf(const CellIndex& tile, int tile_blocks, double resolution);
/// Throws std::invalid_argument naming `what` unless tile_blocks is in 1..kMaxTileBlocks.
void checkTileBlocks(int tile_blocks, const std::string& what);

class TiledMapFile {
 public:
  /// Reads and checks the header and the index (not the tiles). Throws MapFormatError or
  /// std::runtime_error (unreadable file), naming `path`.
  explicit TiledMapFile(std::string path);

  const std::string& path() const { return path_; }
  const MapOptions& options() const { return options_; }
  int tileBlocks() const { return tile_blocks_; }
  double tileEdgeMetres() const;
  const std::vector<TileInfo>& tiles() const { return tiles_; }
  /// The space a tile covers.
  Eigen::AlignedBox3d tileBox(const CellIndex& tile) const;

  /// One tile as a map (the map's options; `memory_budget` as loadMap()).
  NdtMap loadTile(const TileInfo& tile, uint64_t memory_budget = defaultMemoryBudget()) const;
  /// Every tile that meets `region`, in one map.
  NdtMap loadRegion(const Eigen::AlignedBox3d& region,
                    uint64_t memory_budget = defaultMemoryBudget()) const;
  /// The whole map. Past the budget: MemoryBudgetError naming the file and the tile.
  NdtMap loadAll(uint64_t memory_budget = defaultMemoryBudget()) const;
  /// Copies a loaded tile's cells into `map` (same options; its cells must be unknown there):
  /// for callers that keep tiles resident by region.
  static void addTile(const NdtMap& tile, NdtMap& map);
  /// "PATH tile (x, y, z)": how errors name a tile.
  std::string tileSource(const TileInfo& tile) const;

 private:
  NdtMap loadTilesWhere(const std::function<bool(const CellIndex&)>& wanted,
                        uint64_t memory_budget) const;

  std::string path_;
  MapOptions options_;
  int tile_blocks_ = 1;
  std::vector<TileInfo> tiles_;
};

}  // namespace ndtom
