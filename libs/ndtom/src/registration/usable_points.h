// The one rule for which scan points registration and localization use.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "support/parallel.h"

namespace ndtom::registration {

/// Farther points are glitches, whatever max_range says (m).
inline constexpr double kMaxUsableRange = 1e6;

/// The points of `scan` (sensor frame) that are finite, within [min_range, max_range] of the
/// sensor and under kMaxUsableRange, and whose cells a grid of `cell_size` can index.
std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          double min_range, double max_range, double cell_size);
/// The same, filtered on up to `threads.threads` threads, in the scan's order.
std::vector<Eigen::Vector3d> usablePoints(const std::vector<Eigen::Vector3d>& scan,
                                          double min_range, double max_range, double cell_size,
                                          Threads threads);

}  // namespace ndtom::registration
