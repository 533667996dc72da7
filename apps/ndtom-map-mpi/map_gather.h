// Putting a distributed build's map together: each process's part (its own tiles' cells,
// disjoint from every other's) is encoded, sent to process 0 and absorbed there.
#pragma once

#include <mpi.h>

#include <cstdint>

#include "ndtom/map/ndt_map.h"

namespace ndtom::mapper {

/// Collective. Returns the whole map on process 0 (an empty map elsewhere); `bytes_sent` gets
/// what this process sent (0 on process 0, whose part stays in memory).
NdtMap gatherMap(NdtMap part, MPI_Comm comm, uint64_t& bytes_sent);

}  // namespace ndtom::mapper
