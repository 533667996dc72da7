// What the scan source and the outputs need, from ndtom-map's command line and the resolved
// insertion options: shared by ndtom-map, ndtom-map-mpi and ndtom-rank-model, so all read and
// write alike.
#pragma once

#include "ndtom_apps/insertion_settings.h"
#include "ndtom_apps/map_outputs.h"
#include "ndtom_apps/mapper_options.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::mapper {

apps::SourceSettings sourceSettingsFor(const MapperOptions& o, const InsertionOptions& insertion);
OutputSettings outputSettingsFor(const MapperOptions& o, const InsertionOptions& insertion);

}  // namespace ndtom::mapper
