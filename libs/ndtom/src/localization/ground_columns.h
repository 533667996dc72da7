// Where a sensor can stand in a map: the heights of the ground in each x, y column, from the
// map's flat occupied Gaussians.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ndtom/map/ndt_map.h"

namespace ndtom::global {

struct GroundColumn {
  Eigen::Vector2d centre;  ///< of the column (m)
  double z = 0;            ///< ground height: the lowest flat Gaussian's mean (m)
};

/// One entry per column of edge `step` holding a Gaussian whose normal (thinnest axis) is
/// within `max_slope_deg` of vertical; ascending column order.
std::vector<GroundColumn> groundColumns(const NdtMap& map, double step, double max_slope_deg);

}  // namespace ndtom::global
