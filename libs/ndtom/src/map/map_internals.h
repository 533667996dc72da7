// The map's private parts, for the library's code that builds or moves whole blocks
// (insertion, block moves, spill files) without going cell by cell through setCell().
// Private to the library.
#pragma once

#include <cstddef>
#include <memory>

#include "map/map_block.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

struct MapInternals {
  static BlockGrid<MapBlock>& grid(NdtMap& map) { return map.grid_; }
  static const BlockGrid<MapBlock>& grid(const NdtMap& map) { return map.grid_; }
  /// Blocks that arrive or leave by other ways than setCell(): their known cells and
  /// statistics bytes are added to the map's counts, modulo 2^64 (0 - n takes n away).
  static void countBlocks(NdtMap& map, size_t cells, size_t stats_bytes) {
    map.num_cells_ += cells;
    map.stats_bytes_ += stats_bytes;
  }
  static size_t statsBytes(const NdtMap& map) { return map.stats_bytes_; }
  static void touch(NdtMap& map) { map.touch(); }
  static StatsChanges& statsChanges(NdtMap& map) { return map.stats_changes_; }
  static std::unique_ptr<ScanScratch, ScanScratchDeleter>& scratch(NdtMap& map) {
    return map.scratch_;
  }
};

}  // namespace ndtom
