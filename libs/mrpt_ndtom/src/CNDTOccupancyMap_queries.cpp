// CNDTOccupancyMap: what the map says about points and rays, its extent, and the nearest
// Gaussian in the plane.
#include <cmath>
#include <limits>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace mrpt_ndtom {
using Eigen::Vector3d;

namespace {
Vector3d toEigen(const mrpt::math::TPoint3D& p) {
  return {p.x, p.y, p.z};
}
}  // namespace

bool CNDTOccupancyMap::getPointOccupancy(float x, float y, float z, double& prob_occupancy) const {
  const std::optional<double> p = m_map.occupancyProbability(Vector3d(x, y, z));
  if (!p) return false;
  prob_occupancy = *p;
  return true;
}

ndtom::CellState CNDTOccupancyMap::cellState(const mrpt::math::TPoint3D& point) const {
  return ndtom::stateAt(m_map, toEigen(point));
}

bool CNDTOccupancyMap::castRay(const mrpt::math::TPoint3D& origin,
                               const mrpt::math::TPoint3D& direction, mrpt::math::TPoint3D& end,
                               bool ignoreUnknownCells, double maxRange) const {
  const Vector3d o = toEigen(origin);
  double range = maxRange;
  if (!(range > 0)) {  // to the farthest corner of the known cells
    if (m_map.isEmpty()) return false;
    const mrpt::math::TBoundingBox box = boundingBox();
    range = 0;
    for (const double x : {box.min.x, box.max.x})
      for (const double y : {box.min.y, box.max.y})
        for (const double z : {box.min.z, box.max.z})
          range = std::max(range, (Vector3d(x, y, z) - o).norm());
  }
  const auto hit = ndtom::castRay(m_map, o, toEigen(direction), range, !ignoreUnknownCells);
  if (!hit) return false;
  const Vector3d centre = m_map.geometry().cellCenter(hit->cell);
  end = {centre.x(), centre.y(), centre.z()};
  return true;
}

mrpt::math::TBoundingBox CNDTOccupancyMap::boundingBox() const {
  if (m_map.isEmpty()) return {{0, 0, 0}, {0, 0, 0}};
  ndtom::CellIndex lo{INT32_MAX, INT32_MAX, INT32_MAX}, hi{INT32_MIN, INT32_MIN, INT32_MIN};
  m_map.forEachCell([&](const ndtom::CellView& c) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], c.index[a]);
      hi[a] = std::max(hi[a], c.index[a]);
    }
  });
  const ndtom::GridGeometry& g = m_map.geometry();
  return {{g.cellMin(lo.x), g.cellMin(lo.y), g.cellMin(lo.z)},
          {g.cellMin(hi.x + 1), g.cellMin(hi.y + 1), g.cellMin(hi.z + 1)}};
}

float CNDTOccupancyMap::squareDistanceToClosestCorrespondence(float x0, float y0) const {
  std::shared_ptr<const ndtom::PointKdTree> tree;
  {
    const auto lookup = gaussianLookup();
    std::lock_guard<std::mutex> lock(m_lookup_mutex);
    if (!m_means_xy) {
      std::vector<Vector3d> flat;
      flat.reserve(lookup->size());
      lookup->forEachGaussian(
          [&](const auto& g) { flat.emplace_back(g.mean.x(), g.mean.y(), 0.0); });
      m_means_xy = std::make_shared<const ndtom::PointKdTree>(flat);
    }
    tree = m_means_xy;
  }
  std::vector<ndtom::PointKdTree::Neighbour> nearest;
  tree->nearest(Vector3d(x0, y0, 0.0), 1, std::numeric_limits<double>::infinity(), nearest);
  return nearest.empty() ? std::numeric_limits<float>::infinity()
                         : float(nearest.front().squared_distance);
}

}  // namespace mrpt_ndtom
