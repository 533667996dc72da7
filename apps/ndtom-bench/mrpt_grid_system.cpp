#include "mrpt_grid_system.h"

#include <mrpt/maps/COccupancyGridMap3D.h>

#include <algorithm>
#include <cstdlib>

namespace ndtom::bench {

namespace {

mrpt::math::TPoint3D toTPoint(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

}  // namespace

MrptGridSystem::MrptGridSystem(double resolution, double max_range, const Box& bounds)
    : resolution_(resolution), max_range_(max_range), bounds_(bounds) {}

MrptGridSystem::~MrptGridSystem() = default;

void MrptGridSystem::reset() {
  grid_.reset();
  const Eigen::Vector3d lo = bounds_.min.array() - resolution_;
  const Eigen::Vector3d hi = bounds_.max.array() + resolution_;
  grid_ = std::make_unique<mrpt::maps::COccupancyGridMap3D>(toTPoint(lo), toTPoint(hi),
                                                            float(resolution_));
}

// insertPointCloud(sensor, points, maxValidRange) in 2.5.8 calls insertRay(sensor, point) for
// every point and ignores maxValidRange, so the max range is applied here, as a user must.
void MrptGridSystem::insertScan(const Scan& scan) {
  const mrpt::math::TPoint3D sensor = toTPoint(scan.origin);
  for (const Eigen::Vector3d& p : scan.points) {
    const Eigen::Vector3d ray = p - scan.origin;
    const double range = ray.norm();
    if (range <= max_range_) {
      grid_->insertRay(sensor, toTPoint(p), true);
    } else {
      grid_->insertRay(sensor, toTPoint(scan.origin + ray * (max_range_ / range)), false);
    }
  }
}

uint64_t MrptGridSystem::lastScanVisits(const Scan& scan) {
  const auto& g = grid_->m_grid;
  const int sx = g.x2idx(scan.origin.x()), sy = g.y2idx(scan.origin.y());
  const int sz = g.z2idx(scan.origin.z());
  uint64_t visits = 0;
  for (const Eigen::Vector3d& p : scan.points) {
    const Eigen::Vector3d ray = p - scan.origin;
    const double range = ray.norm();
    const Eigen::Vector3d end =
        range <= max_range_ ? p : Eigen::Vector3d(scan.origin + ray * (max_range_ / range));
    const int dx = std::abs(g.x2idx(end.x()) - sx), dy = std::abs(g.y2idx(end.y()) - sy);
    const int dz = std::abs(g.z2idx(end.z()) - sz);
    visits += uint64_t(std::max({dx, dy, dz}));
  }
  return visits;
}

MapSize MrptGridSystem::mapSize() const {
  const auto& g = grid_->m_grid;
  MapSize size;
  size.memory_bytes = g.getVoxelCount() * sizeof(*g.cellByIndex(size_t(0)));
  for (size_t i = 0; i < g.getVoxelCount(); ++i) size.cells += *g.cellByIndex(i) != 0;
  return size;
}

}  // namespace ndtom::bench
