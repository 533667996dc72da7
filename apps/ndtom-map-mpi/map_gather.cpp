#include "ndtom/scale/block_moves.h"
#include "map_gather.h"

#include <vector>

#include "mpi_pieces.h"
#include "ndtom/files/map_io.h"

namespace ndtom::mapper {

NdtMap gatherMap(NdtMap part, MPI_Comm comm, uint64_t& bytes_sent) {
  int rank = 0, ranks = 1;
  MPI_Comm_rank(comm, &rank);
  MPI_Comm_size(comm, &ranks);
  bytes_sent = 0;
  if (rank != 0) {
    const std::vector<uint8_t> bytes = encodeMap(part);
    uint64_t size = bytes.size();
    MPI_Send(&size, 1, MPI_UINT64_T, 0, 0, comm);
    forEachMpiPiece(size, [&](uint64_t offset, int n) {
      MPI_Send(bytes.data() + offset, n, MPI_BYTE, 0, 1, comm);
    });
    bytes_sent = size;
    return NdtMap(part.options());
  }
  // In rank order: the result does not depend on which part arrives first.
  for (int from = 1; from < ranks; ++from) {
    uint64_t size = 0;
    MPI_Recv(&size, 1, MPI_UINT64_T, from, 0, comm, MPI_STATUS_IGNORE);
    std::vector<uint8_t> bytes(size);
    forEachMpiPiece(size, [&](uint64_t offset, int n) {
      MPI_Recv(bytes.data() + offset, n, MPI_BYTE, from, 1, comm, MPI_STATUS_IGNORE);
    });
    NdtMap other = decodeMap(bytes.data(), bytes.size(), "process " + std::to_string(from) +
                                                             "'s part of the map");
    ndtom::absorbBlocks(part, std::move(other));
  }
  return part;
}

}  // namespace ndtom::mapper
