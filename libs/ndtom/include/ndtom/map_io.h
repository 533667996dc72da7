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
// Loading validates everything (checksum, version, sizes, counts, finite values, option
// ranges, duplicate cells) and throws MapFormatError naming the source; it never crashes.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "ndtom/ndt_map.h"

namespace ndtom {

inline constexpr uint32_t kMapFormatVersion = 1;

class MapFormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

std::vector<uint8_t> encodeMap(const NdtMap& map);
/// `source` names the data in error messages (a file name, "MRPT archive", ...).
NdtMap decodeMap(const uint8_t* data, size_t size, const std::string& source = "buffer");

/// Atomic: writes `path`.tmp-<pid> and renames it over `path`, so an interrupted save leaves
/// the previous file intact. Throws std::runtime_error naming the path on failure.
void saveMap(const NdtMap& map, const std::string& path);
/// Throws MapFormatError (bad content) or std::runtime_error (unreadable file).
NdtMap loadMap(const std::string& path);

}  // namespace ndtom
