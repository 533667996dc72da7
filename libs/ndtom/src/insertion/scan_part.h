// One process's part of a distributed build's scan (scale/distributed_insert.h): which tiles'
// cells it changes, and how it shares the rays with the other processes. Private to the
// library.
#pragma once

#include "ndtom/partition/count_exchange.h"
#include "ndtom/partition/tile_ownership.h"

namespace ndtom {

struct ScanPart {
  const TileOwnership& owned;
  /// The rays shared out whole and their counts traded through it (count_exchange.h);
  /// nullptr: the process walks every ray's stretches through its own tiles.
  CountExchange* exchange = nullptr;
};

}  // namespace ndtom
