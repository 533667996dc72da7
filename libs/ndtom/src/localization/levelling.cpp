#include "localization/levelling.h"

#include <algorithm>

namespace ndtom::tracking {

RegistrationOptions levellingOptions(RegistrationOptions o) {
  o.planar = false;
  o.level_only = true;
  o.max_points = std::min<size_t>(o.max_points, 1000);
  return o;
}

std::optional<Eigen::Isometry3d> levelledPose(NdtRegistration& leveller,
                                              const std::shared_ptr<const MapPyramid>& pyramid,
                                              const NdtMap& map,
                                              const std::vector<Eigen::Vector3d>& points,
                                              const Eigen::Isometry3d& pose) {
  leveller.pinPyramid(pyramid, map.revision());
  const size_t finest = std::min(pyramid->size(), leveller.levelsInUse()) - 1;
  const RegistrationResult r =
      leveller.align(map, points, pose, NdtRegistration::Levels{finest, finest + 1});
  if (!r.converged) return std::nullopt;
  return r.pose;
}

}  // namespace ndtom::tracking
