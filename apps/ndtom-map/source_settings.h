// What a scan source needs, from ndtom-map's command line and the resolved insertion options:
// shared by ndtom-map and ndtom-map-mpi, so both read the input alike.
#pragma once

#include "insertion_settings.h"
#include "mapper_options.h"
#include "scan_source.h"

namespace ndtom::mapper {

SourceSettings sourceSettingsFor(const MapperOptions& o, const InsertionOptions& insertion);

}  // namespace ndtom::mapper
