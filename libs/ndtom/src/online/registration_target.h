// What an online mapper registers against: the pyramid of the map's region around the sensor,
// cut again as the sensor moves on. It stays valid while the map grows (no rebuild at every
// insertion unless asked), and its cost is bounded by the region, not by the whole map.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>

#include "ndtom/map/ndt_map.h"
#include "ndtom/online/online_mapper.h"
#include "ndtom/registration/map_pyramid.h"

namespace ndtom::online {

class RegistrationTarget {
 public:
  /// The region of `map` around `sensor`, cut again if the policy of `options` says the one
  /// held is stale. Returns whether it was cut.
  bool update(const NdtMap& map, const Eigen::Isometry3d& sensor, const OnlineMapperOptions& options);
  /// Null before the first update().
  const std::shared_ptr<const MapPyramid>& pyramid() const { return pyramid_; }

 private:
  std::shared_ptr<const MapPyramid> pyramid_;
  uint64_t cut_from_revision_ = 0;  ///< of the map it was cut from; 0: never cut
  Eigen::Isometry3d cut_at_ = Eigen::Isometry3d::Identity();
  int scans_since_cut_ = 0;
};

}  // namespace ndtom::online
