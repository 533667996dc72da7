// Degenerate scenes (flat ground, a corridor, walls parallel to the road): the registration
// slides along what the scan does not constrain. Its covariance shows those directions; the
// pose keeps the prediction along them.
#pragma once

#include <Eigen/Geometry>

#include "ndtom/registration/registration.h"

namespace ndtom::tracking {

/// `registered` with its translation's components along the directions whose standard
/// deviation (from `covariance`, over δ = (v, ω), v in the map frame) exceeds `max_sigma`
/// replaced by `predicted`'s. Returns how many directions were replaced.
int keepPredictionAlongWeakDirections(Eigen::Isometry3d& registered,
                                      const Eigen::Isometry3d& predicted,
                                      const Matrix6d& covariance, double max_sigma);

}  // namespace ndtom::tracking
