// A registration from the prediction that only the free-space check refused fits the map's
// Gaussians: something new stands in space the map saw free, or the map contradicts itself
// (a revisit after drift, a building's side that grazing rays cleared). A pose found from
// elsewhere (the last pose, the search around the prediction) may replace it only if it fits
// the Gaussians at least as well: one that passes the check by turning the scan towards space
// the map has not seen fits less (a sparse lidar at a corner: recovered 1.7 m and 3 m off,
// the map judging 0.67 and 0.32 of the scan against 0.83 and 0.87 at the refused pose).
#pragma once

#include <optional>

#include "ndtom/registration/registration.h"

namespace ndtom::tracking {

/// Whether `candidate` (converged) may replace `refused` (none: it may): a score and a share
/// of the scan's items matched (matched × judged fraction) no lower. If not, `candidate` is
/// marked not converged and its failure says why, naming it as `what` ("the last pose's").
bool replacesRefused(RegistrationResult& candidate,
                     const std::optional<RegistrationResult>& refused, const char* what);

}  // namespace ndtom::tracking
