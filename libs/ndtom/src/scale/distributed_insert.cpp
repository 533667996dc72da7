#include "ndtom/scale/distributed_insert.h"

#include "insertion/scan_updater.h"

namespace ndtom {

InsertionReport insertScanPart(NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Vector3d& sensor_origin, const ScanOptions& options,
                               const TileOwnership& owned) {
  owned.validate();
  const ScanPart part{owned, nullptr};
  return ScanUpdater(map, options, &part).run(points, sensor_origin);
}

InsertionReport insertScanPart(NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Vector3d& sensor_origin, const ScanOptions& options,
                               const TileOwnership& owned, CountExchange& exchange) {
  owned.validate();
  const ScanPart part{owned, &exchange};
  return ScanUpdater(map, options, &part).run(points, sensor_origin);
}

}  // namespace ndtom
