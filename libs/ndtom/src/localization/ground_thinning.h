// On flat ground a spinning lidar's rings fall where the last scans' rings fell when the
// sensor stands still. Registered on every ground point, a moving sensor seems to stop: the
// stall of scan-to-map odometry on roads (KISS-ICP's 31 % drift on ndtom-worldgen's city).
// The ground still fixes height, roll and pitch with a fraction of its points.
#pragma once

#include <Eigen/Core>
#include <vector>

namespace ndtom::tracking {

/// `points` (sensor frame) with only one in `keep_every` of those within `band` (m) of the
/// scan's ground plane (findGround); all of them where no ground is found or keep_every is 1.
std::vector<Eigen::Vector3d> thinGround(const std::vector<Eigen::Vector3d>& points, int keep_every,
                                        double band = 0.15);

}  // namespace ndtom::tracking
