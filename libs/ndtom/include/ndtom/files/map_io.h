// The NDT-OM file format (".ndtom"), version 2. All numbers little-endian; varint = LEB128
// (7 bits a byte, low first), zigzag for signed ones.
//
//   "NDTOMMAP"                      8-byte magic
//   u32 version                     2 (1 is still read, see below)
//   u32 option count, then per option: u8 name length, name (ASCII), f64 value
//   u64 known cell count, u64 block count (blocks of 8^3 cells, block_grid.h)
//   u8 log-odds coding: 0 = dictionary: varint size, then f32 values (most used first);
//                       1 = raw: an f32 per cell (when the dictionary would be larger)
//   per block, in ascending (x, y, z) order:
//     3 zigzag varints     block coordinates minus the previous block's (the first: minus 0)
//     u64 byte mask        bit j: byte j of the 512-bit cell mask is non-zero (never 0)
//     the non-zero bytes   of the cell mask, bit i = cell offsetInBlock() i is known
//     log-odds             of its known cells in offset order; coding 0: where a run starts,
//                          varint 2·index + m (dictionary index; m = 1: longer than one
//                          cell, then varint length − 2); runs continue across blocks;
//                          coding 1: f32 per cell
//     varint S             cells with statistics; if S > 0: ceil(k/8) bytes, bit j: the
//                          block's j-th known cell (of k) has some
//     per such cell:       varint 2N + s, f64 mean[3] (relative to the cell centre) and,
//                          if s = 1, f64 scatter[6] (xx xy xz yy yz zz); s = 0: zero scatter
//   u32 CRC-32 of every byte before it
//
// Version 1 had, after the options, a u64 cell count and per cell: i32 x, i32 y, i32 z, f32
// log-odds, u32 N, and if N > 0 the mean and scatter as above (25 B per known cell on lidar
// maps; version 2 5.9).
//
// Loading validates everything (checksum, version, sizes, counts against the bytes left,
// option values, every cell by the rule of cell_rules.h, block order, duplicate cells) and
// throws MapFormatError naming the source; it never crashes and allocates nothing from an
// unchecked count. A map that saves is a map that loads, bit for bit.
#pragma once

#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "ndtom/map/memory_budget.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom {

inline constexpr uint32_t kMapFormatVersion = 2;
/// The oldest version decodeMap() still reads.
inline constexpr uint32_t kOldestMapFormatVersion = 1;

class MapFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Receives the encoding in pieces, in order.
using MapByteSink = std::function<void(const uint8_t* data, size_t size)>;

std::vector<uint8_t> encodeMap(const NdtMap& map);
/// The same bytes, handed to `sink` in pieces of about 1 MB: no copy of the whole encoding.
void encodeMap(const NdtMap& map, const MapByteSink& sink);
/// The size of encodeMap(map): the map encoded into a counter, its bytes never held.
uint64_t encodedMapSize(const NdtMap& map);

/// `source` names the data in error messages (a file name, "MRPT archive", ...). The map gets
/// `memory_budget` (not stored in files); a map that would exceed it throws MemoryBudgetError.
NdtMap decodeMap(const uint8_t* data, size_t size, const std::string& source = "buffer",
                 uint64_t memory_budget = defaultMemoryBudget());

/// Atomic: writes `path`.ndtom-tmp-<pid> and renames it over `path`, so an interrupted save leaves
/// the previous file intact. Throws std::runtime_error naming the path on failure.
void saveMap(const NdtMap& map, const std::string& path);
/// Throws MapFormatError (bad content), MemoryBudgetError (a file larger than the budget, or a
/// map that would exceed it) or std::runtime_error (unreadable file, not a regular file).
NdtMap loadMap(const std::string& path, uint64_t memory_budget = defaultMemoryBudget());

}  // namespace ndtom
