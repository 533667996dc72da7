#include "ndtom/map/map_queries.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "map/ray_dda.h"

namespace ndtom {

CellState cellState(const NdtMap& map, const CellView& cell) {
  if (!map.options().occupancy.enabled)
    return cell.stats && cell.stats->n > 0 ? CellState::Occupied : CellState::Unknown;
  if (cell.logodds > 0.f) return CellState::Occupied;
  if (cell.logodds < 0.f) return CellState::Free;
  return CellState::Unknown;
}

CellState stateAt(const NdtMap& map, const Eigen::Vector3d& point) {
  const std::optional<CellView> cell = map.cellAt(point);
  return cell ? cellState(map, *cell) : CellState::Unknown;
}

namespace {

// Where the ray enters the box of `cell` (slab method), clamped at 0 for a ray starting inside.
double entryDistance(const GridGeometry& geometry, const CellIndex& cell,
                     const Eigen::Vector3d& origin, const Eigen::Vector3d& unit) {
  double enter = 0;
  for (int a = 0; a < 3; ++a) {
    if (unit[a] == 0) continue;  // parallel: the walk only reaches cells it lies in
    const double lo = geometry.cellMin(cell[a]), hi = geometry.cellMin(cell[a] + 1);
    const double t0 = (lo - origin[a]) / unit[a], t1 = (hi - origin[a]) / unit[a];
    enter = std::max(enter, std::min(t0, t1));
  }
  return enter;
}

}  // namespace

std::optional<RayHit> castRay(const NdtMap& map, const Eigen::Vector3d& origin,
                              const Eigen::Vector3d& direction, double max_range,
                              bool stop_at_unknown) {
  if (!origin.allFinite() || !direction.allFinite() || !std::isfinite(max_range) ||
      max_range < 0)
    throw std::invalid_argument("castRay: origin, direction and max_range must be finite");
  const double length = direction.norm();
  if (!(length > 0)) throw std::invalid_argument("castRay: the direction has zero length");
  const Eigen::Vector3d unit = direction / length;
  const Eigen::Vector3d end = origin + max_range * unit;
  const GridGeometry& geometry = map.geometry();
  if (!geometry.inRange(origin) || !geometry.inRange(end))
    throw std::invalid_argument("castRay: the ray leaves the map's supported range");

  std::optional<CellIndex> found;
  bool blocked = false;
  // The walk visits every cell of [origin, end) in order; `end`'s own cell comes last.
  const auto look = [&](const CellIndex& c) {
    const std::optional<CellView> cell = map.cell(c);
    const CellState state = cell ? cellState(map, *cell) : CellState::Unknown;
    if (state == CellState::Occupied) {
      found = c;
      return false;
    }
    if (stop_at_unknown && state == CellState::Unknown) {
      blocked = true;
      return false;
    }
    return true;
  };
  traverseRay(geometry, origin, end, look);
  if (!found && !blocked) look(geometry.cellOf(end));
  if (!found) return std::nullopt;
  RayHit hit;
  hit.cell = *found;
  hit.distance = std::min(entryDistance(geometry, *found, origin, unit), max_range);
  hit.point = origin + hit.distance * unit;
  return hit;
}

}  // namespace ndtom
