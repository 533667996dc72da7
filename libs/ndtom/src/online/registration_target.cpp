#include "online/registration_target.h"

#include <cmath>

#include "ndtom/map/block_grid.h"
#include "ndtom/online/region_refresh.h"
#include "ndtom/scale/block_moves.h"

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

}  // namespace

bool RegistrationTarget::update(const NdtMap& map, const Eigen::Isometry3d& sensor,
                                const OnlineMapperOptions& o) {
  ++scans_since_cut_;
  if (cut_from_revision_ == map.revision()) return false;  // nothing new to cut
  const RegionRefresh refresh{o.target_refresh_distance, o.target_refresh_angle_deg,
                              o.target_max_scans};
  if (cut_from_revision_ != 0 && !refresh.due(cut_at_, sensor, scans_since_cut_)) return false;
  const double block_edge = kBlockEdge * map.options().resolution;
  const Eigen::Vector3d centre = sensor.translation();
  const NdtMap region = copyBlocks(map, [&](const CellIndex& b) {
    return distanceToBlock(centre, b, block_edge) <= o.target_radius;
  }, /*statistics_only=*/true);
  pyramid_ = std::make_shared<const MapPyramid>(region, o.placement.registration.level_factors, o.threads);
  cut_from_revision_ = map.revision();
  cut_at_ = sensor;
  scans_since_cut_ = 0;
  return true;
}

}  // namespace ndtom::online
