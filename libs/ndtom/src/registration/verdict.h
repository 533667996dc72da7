// Whether a registration placed the scan: the checks after the finest level, so that a wrong
// pose is reported as a failure with its reason, not as converged.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/registration.h"
#include "registration/ndt_objective.h"
#include "registration/scan_levels.h"

namespace ndtom::registration {

/// The fraction of the level's scan items (points or Gaussian means) that `pose` puts in open
/// free space; 0 for a map without occupancy.
double freeFraction(const NdtMap& map, const ScanLevel& level, const Eigen::Isometry3d& pose);

/// The pose's covariance over the free parameters (fixed ones get zero rows and columns), from
/// the finest level's information, and whether the matched terms constrain every free one.
struct PoseCovariance {
  Matrix6d covariance = Matrix6d::Identity();
  bool constrained = false;
};
PoseCovariance poseCovariance(const NdtObjective& finest, const Eigen::Isometry3d& pose,
                              bool planar);

/// Why the registration failed ("" if it did not): the finest level did not converge, too
/// little of the scan matched, too much lies in open free space, or the pose is unconstrained.
std::string verdict(const LevelReport& finest, double free_fraction, bool constrained,
                    const RegistrationOptions& options);

}  // namespace ndtom::registration
