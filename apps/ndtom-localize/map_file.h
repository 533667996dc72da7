// The map to localize in: a .ndtom file (the project's format) or a .ndtommap (an MRPT
// archive holding a CNDTOccupancyMap), told apart by their first bytes.
#pragma once

#include <string>

#include "ndtom/ndt_map.h"

namespace ndtom::localizer {

/// Throws mapper::InputError naming the file if it cannot be read or is not such a map.
ndtom::NdtMap loadMapFile(const std::string& path);

}  // namespace ndtom::localizer
