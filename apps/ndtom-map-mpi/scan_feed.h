// The scans every process of a distributed build inserts, in the same order: each process
// reads the input itself (a shared file system), or process 0 reads and broadcasts them.
#pragma once

#include <mpi.h>

#include <cstdint>
#include <memory>
#include <optional>

#include "ndtom_apps/mpi_options.h"
#include "ndtom_apps/scan_source.h"

namespace ndtom::mapper {

class ScanFeed {
 public:
  /// `source`: the opened input on every process (EachReads) or on process 0 (Broadcast;
  /// null elsewhere). Collective: every process calls next() equally often.
  ScanFeed(ScanInput mode, std::unique_ptr<apps::ScanSource> source, MPI_Comm comm);
  std::optional<apps::Scan> next();
  uint64_t bytesBroadcast() const { return bytes_; }  ///< by process 0, in all

 private:
  ScanInput mode_;
  std::unique_ptr<apps::ScanSource> source_;
  MPI_Comm comm_;
  int rank_ = 0;
  uint64_t bytes_ = 0;
};

}  // namespace ndtom::mapper
