// Moving whole blocks between maps, without copying cells: how the out-of-core map spills and
// reloads tiles, and how a distributed build's parts are put together.
#pragma once

#include <functional>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

/// Moves the blocks of `map` whose coordinates `take` accepts into a new map with its
/// options; `map` keeps the rest.
NdtMap extractBlocks(NdtMap& map, const std::function<bool(const CellIndex& block)>& take);
/// extractBlocks for the blocks with coordinates in [lo, hi] on every axis (a tile): looks the
/// range's blocks up one by one where that is cheaper than visiting every block.
NdtMap extractBlockRange(NdtMap& map, const CellIndex& lo, const CellIndex& hi);
/// Copies the blocks of `map` whose coordinates `take` accepts into a new map with its
/// options (a region to register against while `map` goes on growing); with
/// `statistics_only`, only those holding some cell statistics (all a registration pyramid
/// reads: most blocks hold only free space). The copy is not counted against the memory
/// budget: it is the caller's bounded working set.
NdtMap copyBlocks(const NdtMap& map, const std::function<bool(const CellIndex& block)>& take,
                  bool statistics_only = false);
/// Moves every block of `other` into `map`. Throws std::invalid_argument, moving nothing, if
/// the resolutions differ or a block is in both.
void absorbBlocks(NdtMap& map, NdtMap&& other);

}  // namespace ndtom
