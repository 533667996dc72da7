// The command line of ndtom-map-mpi: ndtom-map's options, plus how the processes share the
// work. ndtom-rank-model takes it too, and needs no MPI for it.
#pragma once

#include <string>

#include "ndtom_apps/mapper_options.h"

namespace ndtom::mapper {

/// Where the processes get the scans: each reads the input itself (a shared file system), or
/// process 0 reads and broadcasts them.
enum class ScanInput { EachReads, Broadcast };

/// How the processes share a scan's free-space rays: each walks every ray's stretches
/// through its own tiles (owned_ray_walk.h), or a share of the rays whole, trading counts
/// (count_exchange.h).
enum class RayShare { Tiles, Rays };

struct MpiOptions {
  MapperOptions map;  ///< every ndtom-map option
  ScanInput scan_input = ScanInput::EachReads;
  RayShare ray_share = RayShare::Rays;  ///< less work per process (doc/scale.md)
  int rank_tiles = 1;  ///< edge, in blocks, of the tiles dealt out to the processes
};

/// --rank-tiles when not given. Sharing the rays, small tiles deal the busy tiles along the
/// trajectory out evenly at the cost of a hash per tile a hit or a counted block is in; walking
/// every ray's stretches through a process's own tiles, each tile a ray crosses costs a
/// stretch. Measured in doc/scale.md (rank model, 2 and 16 processes).
inline int defaultRankTiles(RayShare share) { return share == RayShare::Rays ? 1 : 4; }

/// Takes --scan-input and --rank-tiles, hands the rest to parseMapperOptions. Throws
/// apps::UsageError with a one-line message.
MpiOptions parseMpiOptions(int argc, char** argv);
std::string mpiHelpText();

}  // namespace ndtom::mapper
