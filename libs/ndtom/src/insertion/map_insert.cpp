// NdtMap's insertion (paper Sec. III), beside the stages it runs; the map's other members are
// in map/.
#include "insertion/scan_updater.h"

namespace ndtom {

void ScanScratchDeleter::operator()(ScanScratch* scratch) const {
  delete scratch;
}

InsertionReport NdtMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Vector3d& sensor_origin) {
  return insertScan(points, sensor_origin, options_.scan);
}

InsertionReport NdtMap::insertScan(const std::vector<Eigen::Vector3d>& points,
                                   const Eigen::Vector3d& sensor_origin,
                                   const ScanOptions& options) {
  return ScanUpdater(*this, options).run(points, sensor_origin);
}

uint64_t NdtMap::maxScanPoints(uint64_t budget) {
  return budget / ScanUpdater::kBytesPerPoint;
}

}  // namespace ndtom
