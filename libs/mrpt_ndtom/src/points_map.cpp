#include "mrpt_ndtom/points_map.h"

#include <mrpt/maps/CSimplePointsMap.h>

#include "mrpt_ndtom/observation_points.h"

namespace mrpt_ndtom {

const mrpt::maps::CPointsMap* asPointsMap(const mrpt::maps::CMetricMap* map) {
  if (!map) return nullptr;
  if (const auto* points = dynamic_cast<const mrpt::maps::CPointsMap*>(map)) return points;
  return map->getAsSimplePointsMap();  // e.g. a CMultiMetricMap holding one points map
}

std::vector<Eigen::Vector3d> pointsOf(const mrpt::maps::CPointsMap& points,
                                      const mrpt::poses::CPose3D& pose) {
  const Eigen::Isometry3d t = toIsometry(pose);
  const auto &xs = points.getPointsBufferRef_x(), &ys = points.getPointsBufferRef_y(),
             &zs = points.getPointsBufferRef_z();
  std::vector<Eigen::Vector3d> out(xs.size());
  for (size_t i = 0; i < xs.size(); ++i) out[i] = t * Eigen::Vector3d(xs[i], ys[i], zs[i]);
  return out;
}

}  // namespace mrpt_ndtom
