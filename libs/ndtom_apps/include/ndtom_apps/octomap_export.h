// The map as an OctoMap (.bt): occupied and free space as OctoMap's own tools (octovis,
// binvox converters, the ROS octomap server) read them, for users who already know those.
#pragma once

#include <string>

#include "ndtom/map/ndt_map.h"

namespace ndtom::mapper {

/// Writes `map` as an OctoMap OcTree binary file at the same resolution: every occupied and
/// free cell becomes a leaf with the cell's log-odds (Recursive NDT maps: cells with points,
/// at OctoMap's upper clamp); unknown cells stay unknown. OctoMap's cells have the same
/// bounds as ours (cell i covers [i·r, (i+1)·r)). Throws std::runtime_error for a cell
/// beyond OctoMap's range (±32768 cells from the origin) or a failed write.
void writeOctomapBinary(const ndtom::NdtMap& map, const std::string& path);

}  // namespace ndtom::mapper
