// What a map may hold in a cell: the one rule that NdtMap::setCell() and the file loader apply,
// and that insertion, merge and coarsening keep by construction. A map that saves is a map
// that loads.
#pragma once

#include "ndtom/map/cell_index.h"
#include "ndtom/map/cell_stats.h"
#include "ndtom/map/options.h"

namespace ndtom {

/// Why (index, logodds, stats) cannot be a cell of a map with `options`, or nullptr if it can:
///  - the index is isSupportedCell();
///  - the log-odds is finite and within the clamp bounds;
///  - statistics (N > 0) only where occupancy is off or the log-odds is > 0; their mean,
///    relative to the cell centre, inside the closed cell; their scatter finite, symmetric,
///    positive semi-definite (up to rounding), zero for a single point, and each diagonal
///    entry at most N·resolution² (what N points inside the cell can spread, with slack).
const char* cellProblem(const CellIndex& index, float logodds, const CellStats& stats,
                        const MapOptions& options);

}  // namespace ndtom
