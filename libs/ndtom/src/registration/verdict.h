// Whether a registration placed the scan: the checks after the finest level, so that a wrong
// pose is reported as a failure with its reason, not as converged.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <string>

#include "ndtom/map/ndt_map.h"
#include "ndtom/registration/registration.h"
#include "registration/ndt_objective.h"
#include "registration/scan_levels.h"

namespace ndtom::registration {

/// Where the finest level's scan items land at `pose`, as fractions of them: in open free
/// space, and, without matching a Gaussian, where the map cannot judge them (unknown): a cell
/// never observed, or occupied but with too few points for a Gaussian. Both 0 for a
/// map without occupancy, where unobserved and free space cannot be told apart.
struct SpaceFractions {
  double free = 0;
  double unknown = 0;
};
/// Counted on up to `threads.threads` threads: the same fractions for any count.
SpaceFractions spaceFractions(const NdtMap& map, const NdtObjective& finest, const ScanLevel& level,
                              const Eigen::Isometry3d& pose, Threads threads);

/// The pose's covariance over the free parameters (fixed ones get zero rows and columns), from
/// the finest level's information, and whether the matched terms constrain every free one.
struct PoseCovariance {
  Matrix6d covariance = Matrix6d::Identity();
  bool constrained = false;
};
PoseCovariance poseCovariance(const NdtObjective& finest, const Eigen::Isometry3d& pose,
                              const std::array<bool, 6>& free);

/// Why the registration failed ("" if it did not): the finest level did not converge, too
/// little of the scan could be judged or matched, too much lies in open free space (unless
/// `judge_free_space` is false), or the pose is unconstrained. `result` holds the finest
/// level's figures.
std::string verdict(const RegistrationResult& result, bool constrained,
                    const RegistrationOptions& options, bool judge_free_space = true);

}  // namespace ndtom::registration
