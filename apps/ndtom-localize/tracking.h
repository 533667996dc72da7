// The localization loop: every scan of a source registered in the map, from the previous
// result moved by constant velocity.
#pragma once

#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "ndtom/registration.h"
#include "ndtom_apps/progress.h"
#include "scan_source.h"

namespace ndtom::localizer {

/// What became of one scan.
struct ScanRecord {
  size_t index = 0;
  std::string name;
  double time = 0;
  size_t points = 0;  ///< read (after decimation)
  Eigen::Isometry3d prediction = Eigen::Isometry3d::Identity();
  /// Registrations tried: from the prediction, then (if that failed) from the last pose,
  /// since constant velocity misleads on a jerky platform.
  int attempts = 0;
  ndtom::RegistrationResult result;  ///< of the last attempt
  /// The pose kept: the registration's if it converged, else the prediction.
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

struct TrackingResult {
  std::vector<ScanRecord> scans;
  double seconds = 0;  ///< wall time of the whole loop (reading included)
  size_t converged() const;
};

/// Registers every scan of `source` in `map`, from the constant-velocity prediction and, if
/// that fails, from the last pose. Throws mapper::InputError for unreadable data.
TrackingResult track(const ndtom::NdtMap& map, mapper::ScanSource& source,
                     const Eigen::Isometry3d& initial, const ndtom::RegistrationOptions& options,
                     apps::Progress& progress);

}  // namespace ndtom::localizer
