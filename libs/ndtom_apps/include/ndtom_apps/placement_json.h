// The registration and recovery options of a scan placement, as the programs' summaries
// (ndtom-localize, ndtom-slam) state them.
#pragma once

#include "ndtom/localization/scan_placer.h"
#include "ndtom_apps/json_writer.h"

namespace ndtom::apps {

/// The options' fields in the current JSON object: method, level_factors, ..., threads of the
/// registration, then recovery_radius, recovery_yaw_deg, ground_thinning, retry_without_finest,
/// weak_direction_sigma.
void writePlacementOptions(JsonWriter& json, const PlacementOptions& options);

}  // namespace ndtom::apps
