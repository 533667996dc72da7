// Insertion for one process of a distributed build (ndtom-map-mpi): space is cut into tiles
// owned by the processes (partition/tile_ownership.h); every process inserts every scan, in
// the same order, and changes only the cells of its own tiles, exactly as NdtMap::insertScan
// would change them. Cells are independent under insertion, so the processes' maps put
// together are the serial map, bit for bit, clamping included.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "ndtom/map/ndt_map.h"
#include "ndtom/partition/count_exchange.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

/// Walks only the rays' stretches through the tiles `owned` owns; needs no messages. The
/// report's point counts are the scan's; its cell counts are of the owned tiles (with
/// per-point rays cells_hit too). Throws std::invalid_argument for an invalid ownership, and
/// otherwise as NdtMap::insertScan, the map unchanged.
InsertionReport insertScanPart(NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Vector3d& sensor_origin, const ScanOptions& options,
                               const TileOwnership& owned);

/// The rays shared out instead of their stretches: this process walks its share of the scan's
/// rays through every tile and trades counts with the other processes through `exchange`,
/// which every process must call for every scan. With per-point rays its share is a share of
/// the points: it classifies only those, and trades their hits and point counts too, so the
/// report's point counts are still the scan's. The same cells change, to the same values.
/// Throws std::runtime_error, the map unchanged, if another process failed on this scan or
/// sent a malformed message.
InsertionReport insertScanPart(NdtMap& map, const std::vector<Eigen::Vector3d>& points,
                               const Eigen::Vector3d& sensor_origin, const ScanOptions& options,
                               const TileOwnership& owned, CountExchange& exchange);

}  // namespace ndtom
