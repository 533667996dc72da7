#include "online/registration_target.h"

#include <cmath>

#include "ndtom/map/block_grid.h"

namespace ndtom::online {
namespace {

/// Distance from `p` to the box of block `b` (m).
double distanceToBlock(const Eigen::Vector3d& p, const CellIndex& b, double block_edge) {
  double squared = 0;
  for (int a = 0; a < 3; ++a) {
    const double lo = double(b[a]) * block_edge, hi = lo + block_edge;
    const double d = p[a] < lo ? lo - p[a] : (p[a] > hi ? p[a] - hi : 0.0);
    squared += d * d;
  }
  return std::sqrt(squared);
}

MapPyramid::BlockFilter regionAround(const Eigen::Vector3d& centre, double radius,
                                     double block_edge) {
  return [=](const CellIndex& b) { return distanceToBlock(centre, b, block_edge) <= radius; };
}

}  // namespace

void RegistrationTarget::update(const NdtMap& map, const Eigen::Isometry3d& sensor,
                                const OnlineMapperOptions& o) {
  const double block_edge = kBlockEdge * map.options().resolution;
  const Eigen::Vector3d centre = sensor.translation();
  if (pyramid_ && pyramid_->follow(map)) {
    if ((centre - region_centre_).norm() >= o.target_refresh_distance) {
      pyramid_->setMembers(map, regionAround(centre, o.target_radius, block_edge));
      region_centre_ = centre;
    }
    return;
  }
  pyramid_ = std::make_shared<MapPyramid>(map, o.placement.registration.level_factors, o.threads,
                                          regionAround(centre, o.target_radius, block_edge));
  region_centre_ = centre;
}

}  // namespace ndtom::online
