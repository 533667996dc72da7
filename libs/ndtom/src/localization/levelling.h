// The levelling pass that follows a registration on a thinned ground (ground_thinning.h): with
// one ground point in many, height, roll and pitch rest on few points, so the pose is
// registered again on the finest level with only those three free, on every point (the
// ground's rings cannot pull x and y). Tracking (ScanPlacer) and loop checks (LoopChecker)
// level their poses so. Private to the library.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <optional>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/map_pyramid.h"
#include "ndtom/registration/registration.h"

namespace ndtom::tracking {

/// The levelling registration's options from the registration levelled: level_only, not
/// planar, at most 1000 points (three parameters, set mostly by the ground: a sixth of the
/// points does; city drive: 35 ms a scan with 6000, roll and pitch within 0.1° over the
/// kilometre all the same with 1000).
RegistrationOptions levellingOptions(RegistrationOptions registration);

/// `pose` of `points` (sensor frame) registered again by `leveller` (made with
/// levellingOptions()) on the finest level of `pyramid` it uses (levelsInUse()), the level
/// the pose was found on;
/// nullopt if the levelling's verdict fails. Throws as NdtRegistration::align.
std::optional<Eigen::Isometry3d> levelledPose(NdtRegistration& leveller,
                                              const std::shared_ptr<const MapPyramid>& pyramid,
                                              const NdtMap& map,
                                              const std::vector<Eigen::Vector3d>& points,
                                              const Eigen::Isometry3d& pose);

}  // namespace ndtom::tracking
