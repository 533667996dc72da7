// The occupied Gaussians of a map `factor` times coarser, made from the cells that hold
// statistics only: what the registration pyramid keeps of NdtMap::coarsened(factor), bit for
// bit, without building the coarse map's free cells (most of a map's cells).
#pragma once

#include <vector>

#include "ndtom/map/gaussian.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom::registration {

/// Each coarse cell's statistics are the RCU merge of its fine cells' in ascending block
/// order, as coarsened() merges them; the Gaussians with N ≥ 3, covariance regularised.
/// A coarse cell is occupied whenever a fine cell with statistics is (with occupancy, only
/// occupied cells hold statistics, and a coarse cell's log-odds is the largest of its cells').
std::vector<Gaussian> occupiedCoarseGaussians(const NdtMap& map, int factor);

}  // namespace ndtom::registration
