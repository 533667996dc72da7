// Stage 5 of a scan's insertion: the map update. Eq. 12 once per touched cell, and the RCU
// merge (Eq. 2, 11) of each hit cell's points. Everything it allocates is allocated before the
// first cell changes, so it cannot fail half-way. Private to the library.
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

#include "insertion/end_groups.h"
#include "insertion/free_rays.h"
#include "insertion/scan_context.h"
#include "insertion/scan_counts.h"
#include "map/map_block.h"
#include "ndtom/map/block_grid.h"
#include "ndtom/map/options.h"

namespace ndtom {

/// The update's buffers, kept from scan to scan.
struct ApplyBuffers {
  std::vector<CountBlock*> other_counts;  ///< [block * (tables - 1) + table - 1], or nullptr
  std::vector<MapBlock*> map_blocks;      ///< the map's block of each tables[0] block
  std::vector<size_t> new_blocks;         ///< tables[0] blocks the map lacks, to create
  std::vector<CellIndex> created_blocks;  ///< map blocks this scan created, for a rollback
  /// What one thread of the update did; a cache line each, as threads count per cell.
  struct alignas(64) Part {
    size_t touched = 0, created = 0, gaussians_gained = 0, gaussians_lost = 0;
    size_t stats_bytes = 0;  ///< change of the map's statistics bytes (modulo 2^64)
  };
  std::vector<Part> parts;
  /// Per hit block (EndGroups::hit_blocks): its map block and, if its cells may gain
  /// statistics, an empty array with room for all the block will have, made before the map
  /// changes; its statistics move there. Else no capacity.
  struct HitTarget {
    MapBlock* block = nullptr;
    std::vector<CellStats> grown;
  };
  std::vector<HitTarget> hit_targets;
  /// Per thread of the free update: cells its rays emptied of statistics.
  struct EmptiedCell {
    CellIndex block;
    int offset;
  };
  std::vector<std::vector<EmptiedCell>> emptied;
  /// False if recording them ran out of memory: the update itself goes on.
  std::atomic<bool> emptied_complete{true};
  std::vector<size_t> hit_part_starts;  ///< hit_blocks ranges of the hit threads
};

/// What the update changed besides the blocks, for the map's own counters.
struct MapChange {
  size_t cells_created = 0;
  size_t stats_bytes = 0;  ///< change of the statistics bytes (modulo 2^64)
};

/// Applies the scan's hit groups and free counts to `grid` (zeroing the counts for the next
/// scan); the cells touched, created, and the Gaussians gained and lost go to `report`.
/// If it throws (out of memory before any cell changed), the grid is as it was.
MapChange applyToMap(const ScanContext& scan, const MapOptions& map_options,
                     const EndGroups& groups, FreeCounts& counts, BlockGrid<MapBlock>& grid,
                     ApplyBuffers& buffers, InsertionReport& report);

}  // namespace ndtom
