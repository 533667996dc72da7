// The map to localize in: a .ndtom file (the project's format) or a .ndtommap (an MRPT
// archive holding a CNDTOccupancyMap), told apart by their first bytes; or a tiled map,
// which RegionMap loads in part.
#pragma once

#include <string>

#include "ndtom/map/ndt_map.h"

namespace ndtom::localizer {

/// Throws apps::InputError naming the file if it cannot be read or is not such a map.
ndtom::NdtMap loadMapFile(const std::string& path);

/// Whether `path` starts as a tiled map (ndtom/files/tiled_map_io.h), to be loaded by region.
bool isTiledMapFile(const std::string& path);

}  // namespace ndtom::localizer
