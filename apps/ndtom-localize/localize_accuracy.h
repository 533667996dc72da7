// How far the localized poses are from a reference trajectory, scan by scan and in all.
// Both are in the map's frame (the map was built from that reference), so no alignment is
// done: the absolute trajectory error is the plain position difference.
#pragma once

#include <optional>

#include "tracking.h"

namespace ndtom::localizer {

struct PoseError {
  double translation = 0;  ///< m
  double rotation = 0;     ///< degrees, angle of R_refᵀ·R
};

/// The error of a localized scan's pose, if it has a reference (lost scans are counted as
/// lost, not by the error of their prediction).
std::optional<PoseError> errorOf(const ScanRecord& scan);

struct Accuracy {
  size_t scans = 0;  ///< localized, with a reference
  double rmse = 0, max = 0;                    ///< translation (m)
  double rotation_rmse = 0, rotation_max = 0;  ///< degrees
};

/// Over the localized scans with a reference; nullopt if there are none.
std::optional<Accuracy> accuracyOf(const TrackingResult& tracking);

}  // namespace ndtom::localizer
