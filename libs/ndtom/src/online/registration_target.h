// What an online mapper registers against: the pyramid of the map's region around the sensor.
// It follows the map scan by scan (only the coarse cells over what the last insertion changed
// are redone) and its region moves with the sensor, so its cost is bounded by what changed,
// not by the region or the whole map.
#pragma once

#include <Eigen/Geometry>
#include <memory>

#include "ndtom/map/ndt_map.h"
#include "ndtom/online/online_mapper.h"
#include "ndtom/registration/map_pyramid.h"

namespace ndtom::online {

class RegistrationTarget {
 public:
  /// Brings the pyramid to `map` as it is now, its region moved around `sensor` once the
  /// sensor is `options.target_refresh_distance` from where the region was last centred.
  /// Builds it anew only the first time, or when the map changed other than by one
  /// insertion since the last call.
  void update(const NdtMap& map, const Eigen::Isometry3d& sensor,
              const OnlineMapperOptions& options);
  /// Null before the first update().
  std::shared_ptr<const MapPyramid> pyramid() const { return pyramid_; }

 private:
  std::shared_ptr<MapPyramid> pyramid_;
  Eigen::Vector3d region_centre_ = Eigen::Vector3d::Zero();
};

}  // namespace ndtom::online
