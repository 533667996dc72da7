// The out-of-core build's spill files: a tile's blocks nearly as they are in memory, written and read
// back by the same process (out_of_core_map.cpp). Not a map file: no portability, no
// compaction; a copy of the blocks with a CRC, so that spilling and reloading cost about a
// memcpy instead of the map format's encoding and cell-by-cell validation.
//
//   "NDTOMSPL", u64 block count, then per block holding a known cell: i32 x, y, z; the known
//   mask (u64 × 8); f32 log-odds per known cell (offset order); the statistics mask (u64 × 8);
//   u32 statistics count, then per cell with statistics (offset order): u32 n, f64 mean[3],
//   f64 scatter[9]; u32 CRC-32 of all before it.
#pragma once

#include <string>

#include "ndtom/files/map_io.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

struct SpillCodec {
  /// The blocks of `map`, in no particular order, to `sink`.
  static void write(const NdtMap& map, const MapByteSink& sink);
  /// The map written by write(), with `options`. Throws MapFormatError naming `source` if the
  /// bytes are not such a file (damaged or cut short).
  static NdtMap read(const std::string& bytes, const MapOptions& options,
                     const std::string& source);
};

}  // namespace ndtom
