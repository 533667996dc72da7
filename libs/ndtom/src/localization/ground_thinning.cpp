#include "localization/ground_thinning.h"

#include <cmath>

#include "ndtom/localization/global_localization.h"

namespace ndtom::tracking {

std::vector<Eigen::Vector3d> thinGround(const std::vector<Eigen::Vector3d>& points, int keep_every,
                                        double band) {
  if (keep_every <= 1) return points;
  const GravityGuess ground = findGround(points, /*max_tilt_deg=*/45);
  if (!ground.found) return points;
  std::vector<Eigen::Vector3d> out;
  out.reserve(points.size());
  size_t on_ground = 0;
  for (const Eigen::Vector3d& p : points) {
    const bool ground_point = std::abs(ground.up.dot(p) + ground.height) < band;
    if (!ground_point || on_ground++ % size_t(keep_every) == 0) out.push_back(p);
  }
  return out;
}

}  // namespace ndtom::tracking
