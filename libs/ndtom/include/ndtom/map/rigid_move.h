// A map moved rigidly, e.g. a keyframe's submap by the correction a pose graph found for it.
// The Gaussians move exactly with their points: each cell's statistics go, rotated, to the
// cell of their moved mean (RCU merge where two land in one cell). Occupancy is resampled:
// rotated cells do not fall on the grid, so each new cell takes the log-odds of the old cell
// its centre came from (no holes inside known space, no cell counted twice). A cell that
// receives statistics keeps at least the log-odds of the cells they came from.
#pragma once

#include <Eigen/Geometry>

#include "ndtom/map/ndt_map.h"

namespace ndtom {

/// `map` moved by `motion` (a point p of the map is at motion · p in the result): same
/// options, same number of points. Throws std::invalid_argument for a non-finite or
/// non-rigid motion, or one that takes a cell beyond the supported range; MemoryBudgetError
/// if the moved map does not fit the options' budget.
[[nodiscard]] NdtMap movedMap(const NdtMap& map, const Eigen::Isometry3d& motion);

}  // namespace ndtom
