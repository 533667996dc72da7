// The command line of ndtom-map-mpi: ndtom-map's options, plus how the processes share the
// work.
#pragma once

#include <string>

#include "ndtom_apps/mapper_options.h"
#include "scan_feed.h"

namespace ndtom::mapper {

/// How the processes share a scan's free-space rays: each walks every ray's stretches
/// through its own tiles (owned_ray_walk.h), or a share of the rays whole, trading counts
/// (count_exchange.h).
enum class RayShare { Tiles, Rays };

struct MpiOptions {
  MapperOptions map;  ///< every ndtom-map option
  ScanInput scan_input = ScanInput::EachReads;
  RayShare ray_share = RayShare::Rays;  ///< less work per process (doc/scale.md)
  int rank_tiles = 4;  ///< edge, in blocks, of the tiles dealt out to the processes
};

/// Takes --scan-input and --rank-tiles, hands the rest to parseMapperOptions. Throws
/// apps::UsageError with a one-line message.
MpiOptions parseMpiOptions(int argc, char** argv);
std::string mpiHelpText();

}  // namespace ndtom::mapper
