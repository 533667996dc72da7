// What the scan source and the outputs need, from ndtom-map's command line and the resolved
// insertion options: shared by ndtom-map and ndtom-map-mpi, so both read and write alike.
#pragma once

#include "insertion_settings.h"
#include "map_outputs.h"
#include "mapper_options.h"
#include "scan_source.h"

namespace ndtom::mapper {

SourceSettings sourceSettingsFor(const MapperOptions& o, const InsertionOptions& insertion);
OutputSettings outputSettingsFor(const MapperOptions& o, const InsertionOptions& insertion);

}  // namespace ndtom::mapper
