// The cell sections of the map file, one codec per format version (map_io.h documents the
// layouts). map_io.cpp writes and checks what surrounds them: magic, version, options, CRC.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "files/byte_io.h"
#include "ndtom/map/ndt_map.h"

namespace ndtom::detail {

/// Version 2: blocks with presence masks, log-odds by dictionary and runs (map_codec_blocks.cpp).
void encodeBlocks(const NdtMap& map, ByteWriter& out);
void decodeBlocks(ByteReader& in, NdtMap& map);

/// Version 1: one record per cell (map_codec_v1.cpp); read only.
void decodeCellRecords(ByteReader& in, NdtMap& map);

/// A scatter matrix as both versions store it: the upper triangle, row by row, as f64.
inline Eigen::Matrix3d readScatter(ByteReader& in) {
  Eigen::Matrix3d m;
  m(0, 0) = in.f64();
  m(0, 1) = m(1, 0) = in.f64();
  m(0, 2) = m(2, 0) = in.f64();
  m(1, 1) = in.f64();
  m(1, 2) = m(2, 1) = in.f64();
  m(2, 2) = in.f64();
  return m;
}

/// Checks a decoded cell by the rule of cell_rules.h and sets it; throws MapFormatError for a
/// bad or duplicate cell, MemoryBudgetError (naming `cells`, the file's count) for a full map.
void setDecodedCell(ByteReader& in, NdtMap& map, const CellIndex& index, float logodds,
                    const CellStats& stats, uint64_t cells);

}  // namespace ndtom::detail
