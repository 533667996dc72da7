// What a map says about a place: the occupancy state of a point, and the first occupied cell
// along a ray (for sensor simulation and visibility checks, as OctoMap's castRay).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <optional>

#include "ndtom/map/cell_index.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

enum class CellState { Unknown, Free, Occupied };

/// p(m | z_1:t) of a cell from its log-odds (Eq. 12 inverted).
inline double occupancyProbability(float logodds) {
  return 1.0 - 1.0 / (1.0 + std::exp(double(logodds)));
}

/// The one occupancy rule: with occupancy on, log-odds > 0 is occupied, < 0 free, 0 (or a
/// never-seen cell) unknown; with occupancy off (Recursive NDT) a cell with points is
/// occupied and nothing is known to be free.
CellState cellState(const NdtMap& map, const CellView& cell);
/// The state of the cell at `point`; Unknown for a cell never seen or a point outside the
/// supported range (NaN included).
CellState stateAt(const NdtMap& map, const Eigen::Vector3d& point);

/// A cell with a Gaussian (N >= 3) that is occupied: what drawings and localization use.
inline bool isOccupiedGaussian(const NdtMap& map, const CellView& cell) {
  return cell.stats && cell.stats->hasGaussian() && cellState(map, cell) == CellState::Occupied;
}

inline bool isOccupied(const NdtMap& map, const Eigen::Vector3d& point) {
  return stateAt(map, point) == CellState::Occupied;
}
inline bool isFree(const NdtMap& map, const Eigen::Vector3d& point) {
  return stateAt(map, point) == CellState::Free;
}
inline bool isUnknown(const NdtMap& map, const Eigen::Vector3d& point) {
  return stateAt(map, point) == CellState::Unknown;
}

struct RayHit {
  CellIndex cell;         ///< the first occupied cell along the ray
  double distance = 0;    ///< from the origin to where the ray enters it (0 inside it)
  Eigen::Vector3d point;  ///< origin + distance · direction
};

/// The first occupied cell the ray from `origin` along `direction` (any length, not zero)
/// enters within `max_range` (m, finite), the origin's own cell included. With
/// `stop_at_unknown`, an unknown cell ends the search with no hit, as a sensor model that
/// does not see through unexplored space would. Throws std::invalid_argument for a
/// non-finite origin, direction or max_range, a zero direction, or a ray leaving the
/// supported range.
std::optional<RayHit> castRay(const NdtMap& map, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction, double max_range,
                              bool stop_at_unknown = false);

}  // namespace ndtom
