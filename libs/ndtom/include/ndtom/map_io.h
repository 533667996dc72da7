// The NDT-OM file format (".ndtom"), version 1. All numbers little-endian.
//
//   "NDTOMMAP"                      8-byte magic
//   u32 version                     1
//   u32 option count, then per option: u8 name length, name (ASCII), f64 value
//   u64 cell count, then per cell:  i32 x, i32 y, i32 z, f32 log-odds, u32 N,
//                                   and if N > 0: f64 mean[3] (relative to the cell centre),
//                                   f64 scatter[6] (xx xy xz yy yz zz)
//   u32 CRC-32 of every byte before it
//
// Loading validates everything (checksum, version, sizes, counts against the bytes left,
// option values, every cell by the rule of cell_rules.h, duplicate cells) and throws
// MapFormatError naming the source; it never crashes and allocates nothing from an unchecked
// count. A map that saves is a map that loads.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "ndtom/memory_budget.h"
#include "ndtom/ndt_map.h"

namespace ndtom {

inline constexpr uint32_t kMapFormatVersion = 1;

class MapFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Receives the encoding in pieces, in order.
using MapByteSink = std::function<void(const uint8_t* data, size_t size)>;

std::vector<uint8_t> encodeMap(const NdtMap& map);
/// The same bytes, handed to `sink` in pieces of about 1 MB: no copy of the whole encoding.
void encodeMap(const NdtMap& map, const MapByteSink& sink);
/// The size of encodeMap(map), without encoding it.
uint64_t encodedMapSize(const NdtMap& map);

/// `source` names the data in error messages (a file name, "MRPT archive", ...). The map gets
/// `memory_budget` (not stored in files); a map that would exceed it throws MemoryBudgetError.
NdtMap decodeMap(const uint8_t* data, size_t size, const std::string& source = "buffer",
                 uint64_t memory_budget = defaultMemoryBudget());

/// Atomic: writes `path`.tmp-<pid> and renames it over `path`, so an interrupted save leaves
/// the previous file intact. Throws std::runtime_error naming the path on failure.
void saveMap(const NdtMap& map, const std::string& path);
/// Throws MapFormatError (bad content), MemoryBudgetError (a file larger than the budget, or a
/// map that would exceed it) or std::runtime_error (unreadable file, not a regular file).
NdtMap loadMap(const std::string& path, uint64_t memory_budget = defaultMemoryBudget());

}  // namespace ndtom
