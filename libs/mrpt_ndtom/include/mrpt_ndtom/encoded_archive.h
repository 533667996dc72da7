// Writing a CNDTOccupancyMap to an MRPT archive with its map's encoding already at hand: a
// program that also saves the map file (ndtom-map writes PREFIX.ndtom and PREFIX.ndtommap)
// encodes the map once instead of twice.
#pragma once

#include <mrpt/serialization/CArchive.h>

#include <cstdint>
#include <vector>

#include "mrpt_ndtom/CNDTOccupancyMap.h"

namespace mrpt_ndtom {

/// Writes `map` to `out`, the same bytes as `out << map`, taking `encoded`, which must be
/// ndtom::encodeMap(map.ndtMap()), as the map's encoding instead of encoding the map again.
/// If the map's insertion options changed since its last insertion (the archive then holds
/// the map under the new options), the map is encoded as `out << map` does.
void writeWithEncodedMap(mrpt::serialization::CArchive& out, const CNDTOccupancyMap& map,
                         const std::vector<uint8_t>& encoded);

}  // namespace mrpt_ndtom
