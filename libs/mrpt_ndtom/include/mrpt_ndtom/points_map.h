// The points of the "other map" MRPT's matching and alignment calls hand us.
#pragma once

#include <mrpt/maps/CPointsMap.h>
#include <mrpt/poses/CPose3D.h>

#include <Eigen/Core>
#include <vector>

namespace mrpt_ndtom {

/// `map` as a points map (itself, or the points map inside e.g. a CMultiMetricMap); null if
/// it has none.
const mrpt::maps::CPointsMap* asPointsMap(const mrpt::maps::CMetricMap* map);

/// The map's points moved by `pose` (its frame in ours).
std::vector<Eigen::Vector3d> pointsOf(const mrpt::maps::CPointsMap& points,
                                      const mrpt::poses::CPose3D& pose = {});

}  // namespace mrpt_ndtom
