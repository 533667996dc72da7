// A drive through a CityWorld: along the streets' centre lines from one crossing to the next
// (turning on quarter circles of 8 m, as a car does),
// preferring streets not driven yet (so the map grows with the distance, as a survey's does),
// never turning back. Poses every `step` metres, the sensor facing the driving direction.
#pragma once

#include <Eigen/Geometry>
#include <vector>

#include "city_world.h"

namespace ndtom::world {

struct RouteSettings {
  double length = 2000;        ///< (m) driven
  double step = 1.0;           ///< (m) between scans
  double sensor_height = 1.8;  ///< (m) above the street
  uint64_t seed = 1;
  /// Rings of blocks kept round the driven streets: the drive stays off the outermost
  /// `margin` streets of each side, so every street it drives has city all around.
  int margin = 0;
};

/// Sensor poses (sensor → world) along the route: length / step + 1 of them, starting at the
/// crossing (margin, margin). Throws std::invalid_argument for a non-positive length or step,
/// or a margin that leaves no block inside.
std::vector<Eigen::Isometry3d> driveThrough(const CityWorld& city, const RouteSettings& route);

}  // namespace ndtom::world
