// Batch NDT (paper Eq. 1): the Gaussian of every cell computed from all points at once.
// The reference the recursive maps are compared against.
#pragma once

#include <Eigen/Core>
#include <unordered_map>
#include <vector>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/cell_stats.h"

namespace ndtom {

/// Statistics per cell, means relative to the cell centre.
using CellStatsMap = std::unordered_map<CellIndex, CellStats, CellIndexHash>;

/// Two-pass mean and scatter of the points of each cell. Non-finite and out-of-range points
/// are skipped.
CellStatsMap batchNdt(const std::vector<Eigen::Vector3d>& points, const GridGeometry& geometry);

}  // namespace ndtom
